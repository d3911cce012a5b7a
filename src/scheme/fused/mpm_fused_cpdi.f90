!> CPDI2 in 1-D (mpm_shape_cpdi; [Sadeghirad 2011], [Sadeghirad 2013], references: docs/theory.md) on a lean
!> path: USL with FLIP, PIC or the blend, for a run without contact or external forces. Every quantity of a
!> CPDI particle comes from the hat at its two corners x1 < x2:
!>   S_I = (N_I(x1) + N_I(x2))/2,   G_I = (N_I(x2) - N_I(x1))/(x2 - x1),
!> so its P2G is the hat's P2G of two half particles at its corners (mass m/2 and momentum m v/2 each; the
!> force -G_I sigma (x2 - x1) = sigma N_I(x1) - sigma N_I(x2), a corner's share +/- sigma), and its G2P the
!> mean of the hat's gathers at the corners (S a = (a(x1) + a(x2))/2, and the strain rate (v(x2) - v(x1))/(x2
!> - x1)), which also move the corners (x_c += dt v(x_c)). A step is then two passes over the particles and
!> their corners, P2G and G2P, each evaluating the hat once per corner (a corner is shared by the particles
!> on either side of it: P2G adds both halves at once), and the generic path's stress update after them:
!> the same operations as the generic path (mpm_schemes, mpm_operations: the shape cache's four-node weights
!> and gradients, about six passes), summed in another order (within round-off of it: test_cures_fused). The
!> corners are the generic path's (the shape cache's, which the checkpoint syncs); the stepper is the generic
!> one with its step replaced.
module mpm_fused_cpdi
   use mpm_kinds, only: dp, i8
   use mpm_grid, only: grid_t
   use mpm_particles, only: particles_t
   use mpm_loads, only: loads_t
   use mpm_pass_totals, only: pass_totals_t
   use mpm_shape, only: transfer_flip, transfer_pic, transfer_blend
   use mpm_shape_range, only: infinity_bits
   use mpm_lanes, only: block_size, lanes, largest_move_t
   use mpm_operations, only: mirror_fold, solve_grid, update_stress, move_block_totals, move_totals
   use mpm_schemes, only: generic_stepper_t
   use mpm_stepper, only: scheme_usl
   implicit none
   private
   public :: cpdi_stepper_t, cpdi_fast

   !> The generic stepper of a CPDI run whose step is the lean one (cpdi_fast says which runs); `moved` takes
   !> the corners' new positions in G2P and then trades places with the shape cache's corners (no copy, no
   !> allocation after the first step).
   type, extends(generic_stepper_t) :: cpdi_stepper_t
      real(dp), allocatable :: moved(:)
   contains
      procedure :: step => cpdi_step
   end type cpdi_stepper_t

contains

   !> Whether a CPDI run takes the lean step: USL, FLIP, PIC or the blend, the updated Lagrangian
   !> formulation, one body (its particles' domains one chain of corners: corner_of(p) = p - 1), no external
   !> forces (the scenes' forces go through the shape cache); the rest stays on the generic path.
   pure logical function cpdi_fast(scheme, transfer, total, particles, loads)
      integer, intent(in) :: scheme, transfer
      logical, intent(in) :: total
      type(particles_t), intent(in) :: particles
      class(loads_t), intent(in) :: loads
      cpdi_fast = scheme == scheme_usl .and. (transfer == transfer_flip .or. transfer == transfer_pic .or. &
                  transfer == transfer_blend) .and. .not. total .and. .not. allocated(particles%body) .and. &
                  .not. loads%external_forces .and. .not. loads%has_particle_forces
   end function cpdi_fast

   !> One USL step (the generic ladder's order): P2G of mass, momentum and force from the corners, the
   !> mirror folds and the solve, G2P with the corners' move and the strain rate, the stress update.
   subroutine cpdi_step(self, loads, particles, grid, dt, t, totals)
      class(cpdi_stepper_t), intent(inout) :: self
      !> (the run's loads and time: none reach this step, cpdi_fast)
      class(loads_t), intent(in) :: loads
      type(particles_t), intent(inout) :: particles
      type(grid_t), intent(inout) :: grid
      real(dp), intent(in) :: dt, t
      type(pass_totals_t), intent(out) :: totals
      real(dp), allocatable :: swap(:)
      real(dp) :: flip
      select case (self%cache%transfer) ! the FLIP fraction of G2P's velocity
      case (transfer_pic)
         flip = 0.0_dp
      case (transfer_blend)
         flip = self%cache%flip_fraction
      case default
         flip = 1.0_dp
      end select
      if (.not. allocated(self%cache%work)) allocate (self%cache%work(particles%count, 3))
      if (.not. allocated(self%moved)) allocate (self%moved(0:particles%count))
      call corner_p2g(self%cache%corners, particles%mass_of, particles%v, particles%stress, grid%origin, grid%inv_dx, &
                      grid%elements, grid%mass, grid%momentum, grid%force, totals%outside, self%cache%stretched)
      call mirror_fold(grid, .true., .false.)
      call mirror_fold(grid, .false., .true.)
      call solve_grid(grid, dt)
      call corner_g2p(self%cache%corners, self%moved, particles%mass_of, particles%x0, particles%x, particles%v, &
                      grid%origin, grid%inv_dx, grid%elements, grid%length, grid%acceleration, grid%velocity, dt, &
                      flip, self%cache%work(:, 3), totals)
      call move_alloc(self%cache%corners, swap)
      call move_alloc(self%moved, self%cache%corners)
      call move_alloc(swap, self%moved)
      call update_stress(self%cache, particles, grid, dt, self%material, totals, strain_rate_gathered=.true.)
   end subroutine cpdi_step

   !> The hat at corners(c) for c = c0 .. c0 + n: grid coordinate s, cell e (the left node's index; a corner on
   !> a node belongs to the cell to its right, the last node to the last cell), local coordinate xi, and
   !> inside = 1 within the grid (0 outside, NaN too: then e = 0 and xi = 0). A loop without a branch or a
   !> floating-point comparison (mpm_shape_range), so that it vectorises.
   pure subroutine corner_hats(corners, c0, n, origin, inv_dx, cells, s, e, xi, inside)
      real(dp), intent(in) :: corners(0:)
      integer, intent(in) :: c0, n, cells
      real(dp), intent(in) :: origin, inv_dx
      real(dp), intent(out) :: s(0:), xi(0:), inside(0:)
      integer, intent(out) :: e(0:)
      integer :: i, flag
      integer(i8) :: below, above
      real(dp) :: t
      do i = 0, n
         t = (corners(c0 + i) - origin)*inv_dx
         below = transfer(t, 0_i8)  ! flag = inside_range(t, 0.0_dp, real(cells, dp)), written out
         above = transfer(real(cells, dp) - t, 0_i8)
         flag = int(1_i8 - ishft(ior(ior(below, above), infinity_bits - below), -63))
         inside(i) = real(flag, dp)
         s(i) = t
         t = merge(t, 0.0_dp, flag == 1)
         e(i) = min(int(t), cells - 1)
         xi(i) = t - e(i)
      end do
   end subroutine corner_hats

   !> 1 when a domain's corners lie in cells at most `apart` = 2 apart (the generic path's four nodes reach
   !> them), else 0: the sign bit of apart - 3, without a branch (a merge kept the loops from vectorising).
   elemental real(dp) function near(apart)
      integer, intent(in) :: apart
      near = real(ishft(apart - 3, -31), dp)
   end function near

   !> The nodes' mass, momentum and internal force from the particles' corners (cleared first): corner c,
   !> between particles c and c + 1 (corner_of(p) = p - 1: one chain), in cell e at xi adds (1 - xi) q to
   !> node e and xi q to node e + 1 for its two halves' q = m/2 and m v/2, and the force sigma_{c+1} -
   !> sigma_c, corner by corner in order. A particle with a corner outside the grid (`outside`, the first)
   !> or whose corners lie in cells more than two apart (`stretched`, the first: the generic path's four
   !> nodes do not reach) adds nothing, as on the generic path.
   subroutine corner_p2g(corners, mass_of, v, stress, origin, inv_dx, cells, mass, momentum, force, outside, stretched)
      real(dp), intent(in) :: corners(0:)
      real(dp), intent(in), contiguous :: mass_of(:), v(:), stress(:)
      real(dp), intent(in) :: origin, inv_dx
      integer, intent(in) :: cells
      real(dp), intent(out), contiguous :: mass(0:), momentum(0:), force(0:)
      integer, intent(inout) :: outside
      integer, intent(out) :: stretched
      integer :: b0, n, i, p, c, last, e(0:block_size)
      real(dp) :: s(0:block_size), xi(0:block_size), inside(0:block_size), w(block_size)
      real(dp) :: hm(0:block_size + 1), hp(0:block_size + 1), sg(0:block_size + 1)
      real(dp) :: qm, qp, qf
      mass = 0.0_dp
      momentum = 0.0_dp
      force = 0.0_dp
      stretched = 0
      hm(0) = 0; hp(0) = 0; sg(0) = 0  ! (no particle left of the first corner)
      do b0 = 1, size(mass_of), block_size
         n = min(block_size, size(mass_of) - b0 + 1)
         ! the block's corners b0 - 1 .. b0 - 1 + n, and its particles' halves (0: none where they add nothing)
         call corner_hats(corners, b0 - 1, n, origin, inv_dx, cells, s, e, xi, inside)
         do i = 1, n
            p = b0 + i - 1
            w(i) = inside(i - 1)*inside(i)*near(e(i) - e(i - 1))
            hm(i) = w(i)*(0.5_dp*mass_of(p))
            hp(i) = hm(i)*v(p)
            sg(i) = w(i)*stress(p)
         end do
         if (outside == 0 .and. minval(inside(0:n)) == 0.0_dp) outside = b0 - 1 + findloc(inside(1:n)*inside(0:n - 1), &
                                                                                                0.0_dp, 1)
         if (stretched == 0 .and. minval(w(1:n)) == 0.0_dp) then
            do i = 1, n
               if (w(i) == 0.0_dp .and. inside(i - 1)*inside(i) /= 0.0_dp) then
                  stretched = b0 + i - 1
                  exit
               end if
            end do
         end if
         ! corner b0 - 2 + i between particles b0 - 2 + i (the block's i - 1; 0: the block before's last) and
         ! b0 - 1 + i; after the last block its last corner, whose right has no particle
         last = n
         if (b0 + n - 1 == size(mass_of)) then
            last = n + 1
            hm(n + 1) = 0; hp(n + 1) = 0; sg(n + 1) = 0
         end if
         do i = 1, last
            c = e(i - 1)
            qm = hm(i - 1) + hm(i)
            qp = hp(i - 1) + hp(i)
            qf = sg(i) - sg(i - 1)
            mass(c) = mass(c) + (1.0_dp - xi(i - 1))*qm
            mass(c + 1) = mass(c + 1) + xi(i - 1)*qm
            momentum(c) = momentum(c) + (1.0_dp - xi(i - 1))*qp
            momentum(c + 1) = momentum(c + 1) + xi(i - 1)*qp
            force(c) = force(c) + (1.0_dp - xi(i - 1))*qf
            force(c + 1) = force(c + 1) + xi(i - 1)*qf
         end do
         hm(0) = hm(n); hp(0) = hp(n); sg(0) = sg(n)
      end do
   end subroutine corner_p2g

   !> G2P from the corners at the step's start (corner_of(p) = p - 1): each corner's hat gathers a and v^L
   !> (0 outside the grid) and gives its moved position x_c + dt v into `moved` (outside: where it was); the
   !> particle's velocity by the transfer, v = f (v + dt S a) + (1 - f) S v (f the FLIP fraction: 1 FLIP, 0
   !> PIC; the products by 1 and 0 are exact), S a = (a1 + a2)/2, S v = (v1 + v2)/2; its strain rate (v2 -
   !> v1)/(x2 - x1) into `rate`; its position the moved domain's centre. The totals as the generic G2P's
   !> (gather_move): sum m (x - X) and the largest move of x + dt S v (before the centre replaces it), the
   !> kinetic energy, the first particle outside.
   subroutine corner_g2p(corners, moved, mass_of, x0, x, v, origin, inv_dx, cells, length, acceleration, velocity, dt, &
                         flip_fraction, rate, totals)
      real(dp), intent(in) :: corners(0:)
      real(dp), intent(out) :: moved(0:)
      real(dp), intent(in), contiguous :: mass_of(:), x0(:)
      real(dp), intent(inout), contiguous :: x(:), v(:)
      real(dp), intent(in) :: origin, inv_dx, length, dt, flip_fraction
      integer, intent(in) :: cells
      real(dp), intent(in), contiguous :: acceleration(0:), velocity(0:)
      real(dp), intent(out), contiguous :: rate(:)
      type(pass_totals_t), intent(inout) :: totals
      integer :: p, b0, n, i, slot, outside, flag, inside_x(block_size), e(0:block_size)
      integer(i8) :: below, above
      real(dp) :: s(0:block_size), xi(0:block_size), inside(0:block_size), ac(0:block_size), vc(0:block_size)
      real(dp) :: sa, sv, w, xm, lo, hi, pic
      real(dp) :: displacement(lanes), kinetic(lanes), move(block_size, 2), db(block_size), kb(block_size)
      type(largest_move_t) :: largest
      lo = origin
      hi = origin + length
      pic = 1.0_dp - flip_fraction
      displacement = 0.0_dp
      kinetic = 0.0_dp
      slot = 1
      outside = 0
      do b0 = 1, size(mass_of), block_size
         n = min(block_size, size(mass_of) - b0 + 1)
         call corner_hats(corners, b0 - 1, n, origin, inv_dx, cells, s, e, xi, inside)
         do i = 0, n
            ac(i) = inside(i)*((1.0_dp - xi(i))*acceleration(e(i)) + xi(i)*acceleration(e(i) + 1))
            vc(i) = inside(i)*((1.0_dp - xi(i))*velocity(e(i)) + xi(i)*velocity(e(i) + 1))
            moved(b0 - 1 + i) = corners(b0 - 1 + i) + inside(i)*dt*vc(i)
         end do
         do i = 1, n
            p = b0 + i - 1
            w = inside(i - 1)*inside(i)*near(e(i) - e(i - 1))
            sa = w*(0.5_dp*(ac(i - 1) + ac(i)))
            sv = w*(0.5_dp*(vc(i - 1) + vc(i)))
            rate(p) = w*((vc(i) - vc(i - 1))*(inv_dx/(s(i) - s(i - 1))))
            v(p) = flip_fraction*(v(p) + dt*sa) + pic*sv
            xm = x(p) + dt*sv
            move(i, slot) = abs(dt*sv)*inv_dx
            below = transfer(xm - lo, 0_i8)
            above = transfer(hi - xm, 0_i8)
            flag = int(1_i8 - ishft(ior(ior(below, above), infinity_bits - below), -63))
            inside_x(i) = flag
            db(i) = mass_of(p)*(xm - x0(p))
            kb(i) = 0.5_dp*mass_of(p)*v(p)*v(p)
            x(p) = 0.5_dp*(moved(p - 1) + moved(p))
         end do
         call move_block_totals(n, b0, db, kb, move, inside_x, slot, largest, displacement, kinetic, outside)
      end do
      call move_totals(displacement, kinetic, largest, move, outside, totals)
   end subroutine corner_g2p
end module mpm_fused_cpdi
