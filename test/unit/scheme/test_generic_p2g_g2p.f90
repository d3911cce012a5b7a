!> The generic P2G and G2P for every shape and velocity transfer: P2G conserves mass and momentum
!> (APIC's affine part adds none) and the internal forces of a free body sum to zero; a G2P after the
!> grid solve keeps the total momentum (XPIC, FMPM and ASFLIP with their grid fields: each of their
!> projections keeps sum m_I w_I of a free body); APIC carries an affine velocity field through P2G and G2P
!> exactly; and the mirror ghost at a fixed end (mpm_grid, mirror_fold) gives on the body's nodes
!> what the body and its explicit mirror image give on a grid without ghosts.
program test_generic_p2g_g2p
   use mpm_kinds, only: dp
   use mpm_errors, only: error_t
   use mpm_grid, only: grid_t, grid_init
   use mpm_particles, only: particles_t, particles_init, per_particle_data
   use mpm_shape, only: shape_cache_t, all_shapes, all_transfers, shape_name, transfer_name, transfer_apic, &
                        shape_extra_cells, shape_cpdi
   use mpm_shape_cpdi, only: cpdi_corners
   use mpm_transfer_steps, only: transfer_mapped, transfer_solved
   use mpm_operations, only: locate_particles, p2g_mass_momentum, solve_grid, g2p, nodal_velocities, mirror_fold
   use mpm_pass_totals, only: pass_totals_t
   use mpm_testing, only: tester_t, tester
   implicit none
   type(tester_t) :: t
   integer :: s, k
   t = tester('test_generic_p2g_g2p')
   if (t%case('conservation')) then
      do s = 1, size(all_shapes)
         do k = 1, size(all_transfers)
            call conservation(all_shapes(s), all_transfers(k))
         end do
      end do
   end if
   if (t%case('affine')) then
      do s = 1, size(all_shapes)
         call affine(all_shapes(s))
      end do
   end if
   if (t%case('mirror')) then
      do s = 1, size(all_shapes)
         if (shape_extra_cells(all_shapes(s)) > 0) call mirror(all_shapes(s))
      end do
   end if
   call t%finish()

contains

   !> A free body (no fixed node) of 7 elements x 3 particles moved off the sub-cell centres, with
   !> random velocities, velocity gradients and stresses (CPDI: each particle's domain its sub-cell's length
   !> about it, the domains overlapping where the particles moved together).
   subroutine free_body(kind, transfer, particles, grid, cache)
      integer, intent(in) :: kind, transfer
      type(particles_t), intent(out) :: particles
      type(grid_t), intent(out) :: grid
      type(shape_cache_t), intent(out) :: cache
      type(error_t), allocatable :: error
      real(dp), allocatable :: r(:)
      integer :: p
      call particles_init(particles, 7, 3, 1.0_dp, 2.5_dp, error)
      call per_particle_data(particles, error)
      allocate (r(particles%count))
      call random_number(r)
      particles%x = particles%x + (r - 0.5_dp)*0.3_dp
      call random_number(r)
      particles%v = 2*r - 1
      call random_number(r)
      particles%stress = 1.0e3_dp*(r - 0.5_dp)
      call random_number(r)
      particles%volume_ratio = 0.9_dp + 0.2_dp*r
      call random_number(r)
      particles%velocity_gradient = r - 0.5_dp
      call grid_init(grid, 7, 7.0_dp, particles%mass, error, margin=2, ghost=2, element_shares=.false.)
      cache%kind = kind
      cache%transfer = transfer
      cache%flip_fraction = 0.7_dp
      cache%order = 3
      cache%alpha = 0.6_dp
      if (kind == shape_cpdi) call cpdi_corners(particles%x, particles%volume0_of, grid%origin, grid%origin + &
                                                grid%length, cache%corners, cache%corner_of, &
                                                body=[(p, p=1, particles%count)]) ! (a body each: domains of their own)
   end subroutine free_body

   subroutine conservation(kind, transfer)
      integer, intent(in) :: kind, transfer
      type(particles_t) :: particles
      type(grid_t) :: grid
      type(shape_cache_t) :: cache
      type(pass_totals_t) :: totals
      character(len=:), allocatable :: name
      real(dp) :: momentum, dt
      name = shape_name(kind)//' '//transfer_name(transfer)//': '
      call free_body(kind, transfer, particles, grid, cache)
      dt = 1.0e-3_dp
      momentum = sum(particles%mass_of*particles%v)
      call locate_particles(cache, grid, particles, totals)
      call t%check(name//'no particle outside', totals%outside == 0)
      call p2g_mass_momentum(cache, particles, grid, with_force=.true.)
      call transfer_mapped(cache, particles, grid)
      call t%check_close(name//'P2G conserves mass', sum(grid%mass), sum(particles%mass_of), rtol=1.0e-14_dp)
      call t%check_close(name//'P2G conserves momentum', sum(grid%momentum), momentum, atol=1.0e-13_dp)
      call t%check_close(name//'internal forces of a free body sum to zero', sum(grid%force), 0.0_dp, &
                         atol=1.0e-11_dp*maxval(abs(grid%force)))
      call solve_grid(grid, dt)
      call transfer_solved(cache, particles, grid, dt)
      call g2p(cache, particles, grid, dt, totals)
      call t%check_close(name//'P2G, solve and G2P conserve momentum', sum(particles%mass_of*particles%v), momentum, &
                         atol=1.0e-12_dp)
   end subroutine conservation

   !> v_p = a + b x_p and C_p = b: APIC's nodal velocities are a + b x_I and G2P returns the same field.
   subroutine affine(kind)
      integer, intent(in) :: kind
      type(particles_t) :: particles
      type(grid_t) :: grid
      type(shape_cache_t) :: cache
      type(pass_totals_t) :: totals
      character(len=:), allocatable :: name
      real(dp), allocatable :: x(:)
      real(dp), parameter :: a = 0.3_dp, b = -1.7_dp
      integer :: i
      name = shape_name(kind)//' apic: '
      call free_body(kind, transfer_apic, particles, grid, cache)
      particles%v = a + b*particles%x
      particles%velocity_gradient = b
      x = particles%x
      call locate_particles(cache, grid, particles, totals)
      call p2g_mass_momentum(cache, particles, grid, with_force=.false.)
      call nodal_velocities(grid)
      do i = 0, grid%elements
         if (grid%mass(i) > 1.0e-3_dp*particles%mass) &
            call t%check_close(name//'nodal velocity a + b x_I', grid%velocity(i), a + b*(grid%origin + i*grid%dx), &
                               atol=1.0e-12_dp)
      end do
      grid%acceleration = 0.0_dp
      call g2p(cache, particles, grid, 0.0_dp, totals)
      call t%check(name//'affine velocity carried through P2G and G2P', maxval(abs(particles%v - (a + b*x))) < 1.0e-12_dp)
      call t%check(name//'velocity gradient carried', maxval(abs(particles%velocity_gradient - b)) < 1.0e-11_dp)
   end subroutine affine

   !> A body on [0, 7] held at x = 0 with a ghost cell, against the body and its mirror image (x -> -x,
   !> v -> -v, same stress and J) on a grid from x = -8 without ghosts: the same nodal mass, momentum
   !> and force on every node x >= dx.
   subroutine mirror(kind)
      integer, intent(in) :: kind
      type(particles_t) :: particles, both
      type(grid_t) :: grid, wide
      type(shape_cache_t) :: cache, cache_wide
      type(pass_totals_t) :: totals
      type(error_t), allocatable :: error
      character(len=:), allocatable :: name
      integer :: n, i, j
      name = shape_name(kind)//' mirror: '
      call free_body(kind, 1, particles, grid, cache)
      particles%x = particles%x + 0.2_dp*particles%x*(7.0_dp - particles%x)/7.0_dp ! a smooth stretch, x(0) = 0
      call grid_init(grid, 7, 7.0_dp, particles%mass, error, margin=2, ghost=1, fixed=[0], element_shares=.false.)
      call t%check(name//'the ghost cell is a mirror', grid%mirror)
      n = particles%count
      call particles_init(both, 7, 6, 1.0_dp, 2.5_dp, error)
      call per_particle_data(both, error)
      both%x = [particles%x, -particles%x]
      both%v = [particles%v, -particles%v]
      both%stress = [particles%stress, particles%stress]
      both%volume_ratio = [particles%volume_ratio, particles%volume_ratio]
      both%mass_of = [particles%mass_of, particles%mass_of]
      both%volume0_of = [particles%volume0_of, particles%volume0_of]
      call grid_init(wide, 7, 7.0_dp, particles%mass, error, margin=2, ghost=8, element_shares=.false.)
      cache_wide%kind = kind
      call locate_particles(cache, grid, particles, totals)
      call p2g_mass_momentum(cache, particles, grid, with_force=.true.)
      call mirror_fold(grid, .false., .true.)  ! the force, as the scheme reflects it before the solve
      call locate_particles(cache_wide, wide, both, totals)
      call p2g_mass_momentum(cache_wide, both, wide, with_force=.true.)
      do i = 2, grid%elements
         j = i - 1 + 8 ! the same position on the wide grid
         ! (a node a particle barely touches has a tiny mass: the two grids' positions round differently, so
         ! the tolerance is a fraction of a particle's mass, not of the node's)
         call t%check_close(name//'nodal mass', grid%mass(i), wide%mass(j), rtol=1.0e-13_dp, &
                            atol=1.0e-13_dp*particles%mass)
         call t%check_close(name//'nodal momentum', grid%momentum(i), wide%momentum(j), atol=1.0e-13_dp)
         call t%check_close(name//'nodal force', grid%force(i), wide%force(j), atol=1.0e-10_dp)
      end do
      call t%check_close(name//'ghost node reflects its partner', grid%momentum(0), -grid%momentum(2), atol=0.0_dp)
   end subroutine mirror
end program test_generic_p2g_g2p
