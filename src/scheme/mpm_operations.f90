!> The generic operations an MPM step is made of, for any shape function (through shape_cache_t),
!> per-particle masses and volumes, the scene's boundary conditions and forces:
!>   P2G:   m_I = sum_p N_Ip m_p,  p_I = sum_p N_Ip m_p v_p,  f_I = -sum_p dN_Ip sigma_p V_p
!>   solve: p_I += dt f_I,  a_I = f_I/m_I,  v_I = p_I/m_I  (empty nodes: 0; fixed nodes held)
!>   G2P:   x_p += dt sum_I N_Ip v_I and the velocity by the cache's transfer:
!>          FLIP  v_p += dt sum_I N_Ip a_I
!>          PIC   v_p  = sum_I N_Ip v_I
!>          blend v_p  = f (v_p + dt sum_I N_Ip a_I) + (1 - f) sum_I N_Ip v_I,  f = flip_fraction
!>          XPIC  v_p  = sum_I N_Ip (v*_I + dt a_I) (mpm_xpic), FMPM v_p = sum_I N_Ip v_k(p^L)_I (mpm_fmpm: as PIC,
!>                on the filtered velocities), ASFLIP (mpm_asflip: v_p and the move from sum N v^n, sum N v^L)
!>          APIC  v_p  = sum_I N_Ip v_I and the velocity gradient C_p ([Jiang 2015], sec. 5.3; references:
!>                docs/theory.md):
!>                C_p = sum_I v_I dN_Ip (hat, GIMP: exact for their piecewise-linear weights) or
!>                C_p = B_p D_p^-1, B_p = sum_I N_Ip v_I (x_I - x_p), D_p = dx^2/4 (quadratic),
!>                dx^2/3 (cubic B-splines); P2G then adds sum_p N_Ip m_p C_p (x_I - x_p) to p_I.
!>   stress: d eps_p = dt sum_I dN_Ip v_I, then the material's update (mpm_material: the run's law)
!> The total-Lagrangian formulation (cache%total, mpm_total_lagrangian) evaluates the weights once at the
!> reference positions, integrates the force over V0_p and gives the laws dF/F; CPDI (mpm_shape_cpdi) takes the
!> volume of the domain between its corners and moves the corners with the grid in G2P.
!> Each is one loop over the particles (or nodes), serial: sweeps run cases on threads, and a run's
!> results are the same on any number of threads. The schemes (mpm_schemes) compose them.
!> Each public operation hands the arrays to a kernel with explicit contiguous dummies: gfortran then
!> keeps addresses in registers (through the derived types' descriptors the loops ran about 2x slower).
module mpm_operations
   use mpm_kinds, only: dp, i8
   use mpm_grid, only: grid_t, solve_range, zero_fixed
   use mpm_particles, only: particles_t
   use mpm_shape, only: shape_cache_t, evaluate_shapes, shape_ugimp, shape_cpgimp, shape_bspline2, shape_bspline3, &
                        shape_cpdi, transfer_pic, transfer_blend, transfer_apic, transfer_xpic, transfer_fmpm, &
                        transfer_asflip
   use mpm_shape_cpdi, only: cpdi_move_corners, cpdi_centres
   use mpm_total_lagrangian, only: log_strain_increment, reference_stress_volume
   use mpm_asflip, only: asflip_update
   use mpm_mirror, only: mirror_even, mirror_odd
   use mpm_pass_totals, only: pass_totals_t
   use mpm_shape_range, only: infinity_bits
   use mpm_lanes, only: block_size, lanes, largest_move_t, add_lanes, lane_total, track_largest_move, furthest_particle
   use mpm_scatter_gather, only: scatter_columns, gather_columns, affine_none, affine_hat, affine_spline
   use mpm_material, only: material_t, update_material, stored_energy, plastic_work
   implicit none
   private

   public :: move_block_totals, move_totals
   public :: locate_particles, p2g_mass_momentum, p2g_internal_force, nodal_velocities, solve_grid, g2p, &
             update_stress, particle_energies, mirror_fold

contains

   !> Shape functions at the start-of-step positions; totals%outside = first particle outside the domain.
   !> In the total-Lagrangian formulation, at the reference positions, once (the box of GIMP is then the
   !> reference one for uGIMP and cpGIMP alike, J = 1; CPDI's domains are the reference ones).
   subroutine locate_particles(cache, grid, particles, totals)
      type(shape_cache_t), intent(inout) :: cache
      type(grid_t), intent(in) :: grid
      type(particles_t), intent(in) :: particles
      type(pass_totals_t), intent(inout) :: totals
      integer :: outside
      if (cache%total) then
         if (.not. cache%evaluated) then
            if (cache%kind == shape_ugimp .or. cache%kind == shape_cpgimp) cache%half_length = 0.5_dp*particles%volume0_of
            call evaluate_shapes(cache, grid, particles%x0, outside)
            if (totals%outside == 0) totals%outside = outside
            cache%evaluated = .true.
         end if
         return
      end if
      select case (cache%kind)
      case (shape_ugimp)  ! the box of the particle's initial length, l_p0 = V0_p / 2 (per unit area), set
         ! once: V0 does not change, and the generic path keeps the particles' order
         if (.not. allocated(cache%half_length)) cache%half_length = 0.5_dp*particles%volume0_of
         call evaluate_shapes(cache, grid, particles%x, outside)
      case (shape_cpgimp) ! stretched with the particle, l_p = l_p0 J_p
         if (.not. allocated(cache%half_length)) allocate (cache%half_length(particles%count))
         cache%half_length = 0.5_dp*particles%volume0_of*particles%volume_ratio
         call evaluate_shapes(cache, grid, particles%x, outside)
      case default
         call evaluate_shapes(cache, grid, particles%x, outside)
      end select
      if (totals%outside == 0) totals%outside = outside
   end subroutine locate_particles

   !> m_I and p_I from the particles (grid fields cleared first); with `with_force` also the internal
   !> force f_I = -sum_p dN_Ip sigma_p V_p, V_p = J_p V0_p, in the same pass. Mass and momentum are
   !> reflected at mirrored fixed ends here; the force once the scene has added its external forces
   !> (the scheme calls mirror_fold for it before the solve).
   subroutine p2g_mass_momentum(cache, particles, grid, with_force)
      type(shape_cache_t), intent(inout) :: cache
      type(particles_t), intent(in) :: particles
      type(grid_t), intent(inout) :: grid
      logical, intent(in) :: with_force
      grid%mass = 0.0_dp
      grid%momentum = 0.0_dp
      if (with_force) grid%force = 0.0_dp
      call scatter(cache, particles, grid, .true., with_force)
      call mirror_fold(grid, .true., .false.)
   end subroutine p2g_mass_momentum

   !> f_I = -sum_p dN_Ip sigma_p V_p, V_p = J_p V0_p (grid force cleared first; reflected at mirrored
   !> ends by the scheme, with the external forces: see p2g_mass_momentum).
   subroutine p2g_internal_force(cache, particles, grid)
      type(shape_cache_t), intent(inout) :: cache
      type(particles_t), intent(in) :: particles
      type(grid_t), intent(inout) :: grid
      grid%force = 0.0_dp
      call scatter(cache, particles, grid, .false., .true.)
   end subroutine p2g_internal_force

   !> The P2G sums, m_I += N_Ip m_p and p_I += N_Ip m_p v_p (`kinematics`), f_I -= dN_Ip sigma_p V_p
   !> (`force`), by scatter_columns (mpm_scatter_gather: a loop compiled per support and set of sums).
   !> APIC's affine momentum, p_I += N_Ip m_p C_p (x_I - x_p) with x_p at the start of the step, goes
   !> into the momentum per unit weight of node k of the support: m_p (v_p + C_p d_p) + (k - 1) m_p C_p
   !> dx, d_p = x(first(p)) - x_p (it sums to zero over I, since sum_I N_Ip x_I = x_p: total momentum
   !> is unchanged).
   subroutine scatter(cache, particles, grid, kinematics, force)
      type(shape_cache_t), intent(inout) :: cache
      type(particles_t), intent(in) :: particles
      type(grid_t), intent(inout) :: grid
      logical, intent(in) :: kinematics, force
      logical :: affine
      call scratch(cache, particles%count)
      affine = kinematics .and. cache%transfer == transfer_apic
      if (force) then ! sigma_p V_p: V_p = J_p V0_p; V0_p (total Lagrangian); CPDI's domain at the step's start
         if (cache%total) then
            call reference_stress_volume(particles%stress, particles%volume0_of, cache%work(:, 1))
         else if (cache%kind == shape_cpdi) then
            call domain_stress_volume(cache%corners, cache%corner_of, particles%stress, cache%work(:, 1))
         else
            cache%work(:, 1) = particles%stress*particles%volume_ratio*particles%volume0_of
         end if
      end if
      if (affine) then ! APIC: the momentum per unit weight q, r in the loop (see scatter_columns)
         call scatter_columns(cache%support, cache%first, cache%weight, cache%gradient, particles%mass_of, &
                              cache%work(:, 2:2), cache%work(:, 1), kinematics, force, grid%mass, grid%momentum, &
                              grid%force, grid%origin, grid%dx, particles%v, particles%velocity_gradient, &
                              cache%position)
      else
         if (kinematics) cache%work(:, 2) = particles%mass_of*particles%v
         call scatter_columns(cache%support, cache%first, cache%weight, cache%gradient, particles%mass_of, &
                              cache%work(:, 2:2), cache%work(:, 1), kinematics, force, grid%mass, grid%momentum, &
                              grid%force, grid%origin, grid%dx)
      end if
   end subroutine scatter

   !> CPDI: sigma_p (x2 - x1), the stress times the particle domain's length between its corners.
   pure subroutine domain_stress_volume(corners, corner_of, stress, stress_volume)
      real(dp), intent(in) :: corners(0:)
      integer, intent(in), contiguous :: corner_of(:)
      real(dp), intent(in), contiguous :: stress(:)
      real(dp), intent(out), contiguous :: stress_volume(:)
      integer :: p
      do p = 1, size(stress)
         stress_volume(p) = stress(p)*(corners(corner_of(p) + 1) - corners(corner_of(p)))
      end do
   end subroutine domain_stress_volume

   !> At a fixed end with ghost cells (grid%mirror), the mirror image of the body beyond it: node
   !> c - j (c = grid%ghost, the fixed node at x = 0) is node c + j reflected. The body's image has the
   !> velocity -v(-x) and the stress sigma(-x) of an odd displacement field, so the image of a
   !> particle adds to node c + j what the particle adds to node c - j, with the sign of momentum and
   !> force reversed; the ghost node then holds the reflection of its partner (m, -p, -f), and the
   !> grid solve gives it -v, -a. This is exact where the solution is odd about the fixed end, as the
   !> elastic bar's (u = 0 there, and u_xx = u_tt/c^2 = 0 without a body force), so the wide shapes
   !> keep their interior accuracy at the fixed end. A body force is reflected the same way (the
   !> image's is the mirror of the body's: the scheme folds the force after the scene's external
   !> forces); its u_xx then jumps at the end, which the B-splines' second order survives (the column:
   !> 2.07-2.08 under USF, USL and MUSL).
   subroutine mirror_fold(grid, with_kinematics, with_force)
      type(grid_t), intent(inout) :: grid
      logical, intent(in) :: with_kinematics, with_force
      if (with_kinematics) then
         call mirror_even(grid, grid%mass)
         call mirror_odd(grid, grid%momentum)
      end if
      if (with_force) call mirror_odd(grid, grid%force)
   end subroutine mirror_fold

   !> v_I = p_I / m_I (zero on empty nodes), fixed nodes held at rest (momentum and velocity zero).
   subroutine nodal_velocities(grid)
      type(grid_t), intent(inout) :: grid
      where (grid%mass > grid%empty_mass)
         grid%velocity = grid%momentum/grid%mass
      elsewhere
         grid%velocity = 0.0_dp
      end where
      call zero_fixed(grid%fixed, grid%momentum)
      call zero_fixed(grid%fixed, grid%velocity)
   end subroutine nodal_velocities

   !> Explicit momentum update with the assembled force: p_I += dt f_I, a_I = f_I/m_I, v_I = p_I/m_I
   !> (empty nodes 0), fixed nodes held; grid%min_node_mass = the lightest node with mass.
   subroutine solve_grid(grid, dt)
      type(grid_t), intent(inout) :: grid
      real(dp), intent(in) :: dt
      call zero_fixed(grid%fixed, grid%force)
      call zero_fixed(grid%fixed, grid%momentum)
      grid%min_node_mass = huge(1.0_dp)
      call solve_range(0, grid%elements, dt, grid%empty_mass, grid%mass, grid%force, grid%momentum, grid%acceleration, &
                       grid%velocity, grid%min_node_mass)
      call zero_fixed(grid%fixed, grid%acceleration)
      call zero_fixed(grid%fixed, grid%velocity)
   end subroutine solve_grid

   !> Velocity (by the cache's transfer) and position update with the start-of-step shape functions;
   !> totals: sum m (x - X), kinetic energy, the largest move (cells) and its particle, the first
   !> particle outside the domain.
   subroutine g2p(cache, particles, grid, dt, totals, strain_rate)
      type(shape_cache_t), intent(inout) :: cache
      type(particles_t), intent(inout) :: particles
      type(grid_t), intent(in) :: grid
      real(dp), intent(in) :: dt
      type(pass_totals_t), intent(inout) :: totals
      !> Also gather sum_I dN_Ip v_I for update_stress (USL: the same nodal velocities; saves a gather).
      logical, intent(in), optional :: strain_rate
      logical :: with_strain_rate, apic, spline
      with_strain_rate = cache%transfer == transfer_asflip ! (ASFLIP's separation test needs sum dN v^L)
      if (present(strain_rate)) with_strain_rate = with_strain_rate .or. strain_rate
      call scratch(cache, particles%count)
      apic = cache%transfer == transfer_apic
      spline = cache%kind == shape_bspline2 .or. cache%kind == shape_bspline3
      if (apic) then
         ! C_p in G2P's loop: with B-splines B_p D_p^-1, B_p = sum_I N_Ip v_I (x_I - x_p) = d_p sum_I N_Ip v_I
         ! + dx sum_k (k - 1) N_k v_k, d_p = x(first(p)) - x_p at the start of the step (|d_p| < 2 dx: no
         ! cancellation); with the hat and GIMP sum_I v_I dN_Ip (B_p D_p^-1 reduces to it for
         ! piecewise-linear weights)
         call gather_move(cache%support, cache%first, cache%weight, cache%gradient, grid%acceleration, grid%velocity, &
                          dt, grid%inv_dx, grid%origin, grid%origin + grid%length, particles%mass_of, particles%x0, &
                          particles%x, particles%v, cache%work, with_strain_rate, &
                          merge(affine_spline, affine_hat, spline), totals, cache%transfer, cache%flip_fraction, &
                          grid%dx, merge(4.0_dp, 3.0_dp, cache%kind == shape_bspline2)*grid%inv_dx**2, &
                          cache%position, particles%velocity_gradient)
      else if (cache%transfer == transfer_xpic) then ! column 1 gathers v* + dt a (mpm_xpic)
         call gather_move(cache%support, cache%first, cache%weight, cache%gradient, cache%grid_work(:, 1), &
                          grid%velocity, dt, grid%inv_dx, grid%origin, grid%origin + grid%length, particles%mass_of, &
                          particles%x0, particles%x, particles%v, cache%work, with_strain_rate, affine_none, totals, &
                          cache%transfer, cache%flip_fraction, grid%dx, 0.0_dp)
      else if (cache%transfer == transfer_asflip) then ! column 1 gathers v^n (mpm_asflip)
         call gather_move(cache%support, cache%first, cache%weight, cache%gradient, cache%grid_work(:, 1), &
                          grid%velocity, dt, grid%inv_dx, grid%origin, grid%origin + grid%length, particles%mass_of, &
                          particles%x0, particles%x, particles%v, cache%work, with_strain_rate, affine_none, totals, &
                          cache%transfer, cache%flip_fraction, grid%dx, 0.0_dp, alpha=cache%alpha, &
                          start_volume_ratio=cache%start_volume_ratio)
      else
         call gather_move(cache%support, cache%first, cache%weight, cache%gradient, grid%acceleration, grid%velocity, &
                          dt, grid%inv_dx, grid%origin, grid%origin + grid%length, particles%mass_of, particles%x0, &
                          particles%x, particles%v, cache%work, with_strain_rate, affine_none, totals, &
                          cache%transfer, cache%flip_fraction, grid%dx, 0.0_dp)
      end if
      if (cache%kind == shape_cpdi .and. .not. cache%total) then ! the domains' corners move with the grid
         call cpdi_move_corners(grid%origin, grid%inv_dx, grid%elements, grid%velocity, dt, cache%corners)
         call cpdi_centres(cache%corners, cache%corner_of, particles%x)
      end if
   end subroutine g2p

   !> The gathers of G2P (column 1 sums N `acceleration`: a, or XPIC's v* + dt a, ASFLIP's v^n; column 2
   !> N v; with `strain_rate` column 3 dN v), the velocity update of the transfer and the move.
   subroutine gather_move(support, first, weight, gradient, acceleration, velocity, dt, inv_dx, lo, hi, mass_of, x0, &
                          x, v, gathered, strain_rate, affine, totals, transfer_kind, flip_fraction, dx, c_factor, &
                          position, velocity_gradient, alpha, start_volume_ratio)
      integer, intent(in) :: support, transfer_kind
      !> ASFLIP's alpha and each particle's J at the start of the step
      real(dp), intent(in), optional :: alpha
      real(dp), intent(in), contiguous, optional :: start_volume_ratio(:)
      !> APIC's velocity gradient C_p, gathered in the same loop: affine_none (no C), affine_hat
      !> (C = sum dN v; it implies the strain rate) or affine_spline (C = c_factor (d_p sum N v + dx
      !> sum_k (k - 1) N_k v_k), d_p = lo + first(p) dx - position(p)), into velocity_gradient
      integer, intent(in) :: affine
      real(dp), intent(in) :: dx, c_factor
      real(dp), intent(in), contiguous, optional :: position(:)
      real(dp), intent(inout), contiguous, optional :: velocity_gradient(:)
      real(dp), intent(in) :: flip_fraction
      integer, intent(in), contiguous :: first(:)
      real(dp), intent(in), contiguous :: weight(:, :), gradient(:, :), acceleration(0:), velocity(0:), mass_of(:), x0(:)
      real(dp), intent(in) :: dt, inv_dx, lo, hi
      real(dp), intent(inout), contiguous :: x(:), v(:)
      !> scratch: sum N a, sum N v per particle, with `strain_rate` sum dN v
      real(dp), intent(inout), contiguous :: gathered(:, :)
      logical, intent(in) :: strain_rate
      type(pass_totals_t), intent(inout) :: totals
      integer :: p, b0, n, i, outside, slot
      real(dp) :: displacement(lanes), kinetic(lanes), moved(block_size, 2)
      integer :: inside(block_size)
      integer(i8) :: below, above
      real(dp) :: displacement_block(block_size), kinetic_block(block_size)
      type(largest_move_t) :: largest
      ! the gathers: one loop over the particles, compiled for each support and each set of sums
      ! (mpm_scatter_gather; it vectorises)
      call gather_columns(support, first, weight, gradient, acceleration, velocity, gathered, strain_rate, affine, lo, dx, &
                          c_factor, position, velocity_gradient)
      select case (transfer_kind)
      case (transfer_pic, transfer_apic, transfer_fmpm) ! (FMPM: on the filtered velocities)
         v = gathered(:, 2)
      case (transfer_xpic)
         v = gathered(:, 1)
      case (transfer_asflip) ! (also sets column 2 to the velocity the particle moves with)
         call asflip_update(alpha, dt, start_volume_ratio, v, gathered)
      case (transfer_blend)
         v = flip_fraction*(v + dt*gathered(:, 1)) + (1.0_dp - flip_fraction)*gathered(:, 2)
      case default ! transfer_flip
         v = v + dt*gathered(:, 1)
      end select
      ! the move and the totals, block by block (branch-free loops, totals in lanes: see mpm_lanes)
      outside = 0
      slot = 1
      displacement = 0.0_dp
      kinetic = 0.0_dp
      do b0 = 1, size(first), block_size
         n = min(block_size, size(first) - b0 + 1)
         do i = 1, n
            p = b0 + i - 1
            x(p) = x(p) + dt*gathered(p, 2)
            moved(i, slot) = abs(dt*gathered(p, 2))*inv_dx
            below = transfer(x(p) - lo, 0_i8)  ! inside(i) = inside_range(x(p), lo, hi), written out
            above = transfer(hi - x(p), 0_i8)
            inside(i) = int(1_i8 - ishft(ior(ior(below, above), infinity_bits - below), -63))
            displacement_block(i) = mass_of(p)*(x(p) - x0(p))
            kinetic_block(i) = 0.5_dp*mass_of(p)*v(p)*v(p)
         end do
         call move_block_totals(n, b0, displacement_block, kinetic_block, moved, inside, slot, largest, displacement, &
                                kinetic, outside)
      end do
      call move_totals(displacement, kinetic, largest, moved, outside, totals)
   end subroutine gather_move

   !> A G2P block's share of the totals (n particles from b0): sum m (x - X) and the kinetic energy in
   !> lanes, the largest move (its slot of `moved`, mpm_lanes), the first particle outside (`inside` 0).
   subroutine move_block_totals(n, b0, displacement_block, kinetic_block, moved, inside, slot, largest, displacement, &
                                kinetic, outside)
      integer, intent(in) :: n, b0, inside(:)
      real(dp), intent(in) :: displacement_block(:), kinetic_block(:), moved(:, :)
      real(dp), intent(inout) :: displacement(lanes), kinetic(lanes)
      integer, intent(inout) :: slot, outside
      type(largest_move_t), intent(inout) :: largest
      call add_lanes(n, displacement_block, displacement)
      call add_lanes(n, kinetic_block, kinetic)
      call track_largest_move(n, b0, moved, slot, largest)
      if (outside == 0 .and. minval(inside(1:n)) == 0) outside = b0 - 1 + findloc(inside(1:n), 0, 1)
   end subroutine move_block_totals

   !> G2P's totals from its blocks' (move_block_totals).
   subroutine move_totals(displacement, kinetic, largest, moved, outside, totals)
      real(dp), intent(in) :: displacement(lanes), kinetic(lanes), moved(:, :)
      type(largest_move_t), intent(in) :: largest
      integer, intent(in) :: outside
      type(pass_totals_t), intent(inout) :: totals
      totals%displacement = lane_total(displacement)
      totals%kinetic_energy = lane_total(kinetic)
      totals%max_cell_move = largest%value
      totals%furthest = furthest_particle(largest, moved)
      if (totals%outside == 0) totals%outside = outside
   end subroutine move_totals

   !> Strain increment d eps = dt sum_I dN_Ip v_I and the material's update (its law, with the run's
   !> parameters or each particle's where the scene gave them); totals: strain energy, min J, plastic work.
   subroutine update_stress(cache, particles, grid, dt, material, totals, strain_rate_gathered)
      type(shape_cache_t), intent(inout) :: cache
      type(particles_t), intent(inout) :: particles
      type(grid_t), intent(in) :: grid
      real(dp), intent(in) :: dt
      type(material_t), intent(in) :: material
      type(pass_totals_t), intent(inout) :: totals
      !> g2p gathered sum dN v with the same nodal velocities (USL)
      logical, intent(in), optional :: strain_rate_gathered
      logical :: gathered
      gathered = .false.
      if (present(strain_rate_gathered)) gathered = strain_rate_gathered
      call scratch(cache, particles%count)
      if (gathered) then
         cache%work(:, 1) = dt*cache%work(:, 3)
      else
         call gather_strain(cache%support, cache%first, cache%gradient, grid%velocity, dt, cache%work(:, 1))
      end if
      if (cache%total) call log_strain_increment(particles%volume_ratio, cache%work(:, 1)) ! (dF into dF/F)
      call update_material(material, cache%work(:, 1), particles, totals%strain_energy, totals%min_volume_ratio, &
                           totals%plastic_work)
   end subroutine update_stress

   subroutine gather_strain(support, first, gradient, velocity, dt, dstrain)
      integer, intent(in) :: support
      integer, intent(in), contiguous :: first(:)
      real(dp), intent(in), contiguous :: gradient(:, :), velocity(0:)
      real(dp), intent(in) :: dt
      real(dp), intent(out), contiguous :: dstrain(:)
      integer :: p, k
      do p = 1, size(first)
         dstrain(p) = gradient(p, 1)*velocity(first(p))
      end do
      do k = 2, support
         do p = 1, size(first)
            dstrain(p) = dstrain(p) + gradient(p, k)*velocity(first(p) + k - 1)
         end do
      end do
      dstrain = dt*dstrain
   end subroutine gather_strain

   !> The operations' scratch arrays, allocated on first use.
   subroutine scratch(cache, count)
      type(shape_cache_t), intent(inout) :: cache
      integer, intent(in) :: count
      if (.not. allocated(cache%work)) allocate (cache%work(count, 3))
   end subroutine scratch

   !> Kinetic and stored energy, plastic work and the smallest J of the particles as they are (the initial
   !> state).
   subroutine particle_energies(particles, material, totals)
      type(particles_t), intent(in) :: particles
      type(material_t), intent(in) :: material
      type(pass_totals_t), intent(out) :: totals
      totals%kinetic_energy = sum(0.5_dp*particles%mass_of*particles%v**2)
      totals%strain_energy = stored_energy(material, particles)
      totals%plastic_work = plastic_work(material, particles)
      totals%min_volume_ratio = minval(particles%volume_ratio)
   end subroutine particle_energies
end module mpm_operations
