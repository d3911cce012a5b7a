!> One step of each scheme against a hand computation, on the fused kernels and on the generic path.
!> Set-up: one element of length 2 (dx = 2, nodes at 0 and 2, node 0 fixed), two particles at
!> x = 0.5 and 1.5 (the sub-cell centres), density 3 (mass 3, volume 1 each), E = 4, dt = 0.1,
!> velocities 1 and 2, stresses 0.5 and -1.
!> Shape functions: particle 1 (xi = 1/4): N = (3/4, 1/4); particle 2 (xi = 3/4): N = (1/4, 3/4);
!> dN = (-1/2, +1/2). Nodal mass m_1 = 3 (3/4 + 1/4) = 3; p_1 = 3 (1/4 * 1 + 3/4 * 2) = 5.25.
program test_scheme_step
   use mpm_kinds, only: dp
   use mpm_errors, only: error_t
   use mpm_grid, only: grid_t, grid_init
   use mpm_particles, only: particles_t, particles_init
   use mpm_transfer, only: pass_totals_t
   use mpm_fused, only: fused_start, fused_step
   use mpm_segments, only: segments_t
   use mpm_schemes, only: scheme_usf, scheme_usl, scheme_musl, scheme_step
   use mpm_testing, only: tester_t, tester
   use mpm_particles, only: per_particle_data
   use mpm_shape, only: shape_cache_t
   use mpm_scene_bar, only: bar_t, bar_init
   implicit none
   type(tester_t) :: t
   real(dp), parameter :: dt = 0.1_dp, youngs = 4.0_dp, m = 3.0_dp, dx = 2.0_dp
   real(dp) :: f1, p1, a1, v1, de, v_expected(2), x_expected(2), s_expected(2), j_expected(2), stress(2)
   type(grid_t) :: grid
   type(particles_t) :: particles
   type(pass_totals_t) :: totals
   type(segments_t) :: seg
   type(shape_cache_t) :: cache
   type(bar_t) :: bar

   t = tester('test_scheme_step')
   bar = bar_init(dx, youngs, 3.0_dp, 0.0_dp, 1)  ! the generic steps' scene: boundary data only, no force

   ! USL: force from the current stresses: sum sigma V = 0.5 - 1 = -0.5, f_1 = -dN_1 * (-0.5) = +0.25.
   if (t%case('usl')) then
      call setup()
      call fused_start(scheme_usl, particles, grid, seg, totals)
      call fused_step(scheme_usl, particles, grid, seg, dt, youngs, totals)
      f1 = 0.25_dp
      p1 = 5.25_dp + dt*f1
      a1 = f1/m
      v1 = p1/m
      v_expected = [1.0_dp + dt*0.25_dp*a1, 2.0_dp + dt*0.75_dp*a1]
      x_expected = [0.5_dp + dt*0.25_dp*v1, 1.5_dp + dt*0.75_dp*v1]
      de = dt*v1/dx
      s_expected = [0.5_dp, -1.0_dp] + youngs*de
      j_expected = 1.0_dp + de
      call compare('usl')
      call setup_generic()
      call scheme_step(scheme_usl, bar, cache, particles, grid, dt, youngs, 0.0_dp, totals)
      call compare('generic usl')
      call compare_totals('generic usl')
   end if

   ! USF: strain first from v_1 = p_1/m_1 = 1.75: d eps = 0.1 * 1.75 / 2 = 0.0875;
   ! stresses 0.85, -0.65; J = 1.0875; sum sigma V = 0.2 * 1.0875; f_1 = -(1/2)(0.2175) = -0.10875.
   if (t%case('usf')) then
      call setup()
      call fused_start(scheme_usf, particles, grid, seg, totals)
      call fused_step(scheme_usf, particles, grid, seg, dt, youngs, totals)
      de = dt*1.75_dp/dx
      s_expected = [0.5_dp, -1.0_dp] + youngs*de
      j_expected = 1.0_dp + de
      f1 = -0.5_dp*sum(s_expected*j_expected*1.0_dp)
      call t%check_close('usf hand force', f1, -0.10875_dp, rtol=1.0e-14_dp)
      p1 = 5.25_dp + dt*f1
      a1 = f1/m
      v1 = p1/m
      v_expected = [1.0_dp + dt*0.25_dp*a1, 2.0_dp + dt*0.75_dp*a1]
      x_expected = [0.5_dp + dt*0.25_dp*v1, 1.5_dp + dt*0.75_dp*v1]
      call compare('usf')
      call setup_generic()
      call scheme_step(scheme_usf, bar, cache, particles, grid, dt, youngs, 0.0_dp, totals)
      call compare('generic usf')
      call compare_totals('generic usf')
   end if

   ! MUSL: as USL, then the new particle momentum mapped back: p_1 = 3 (1/4 v_1' + 3/4 v_2'),
   ! and the strain from that nodal velocity.
   if (t%case('musl')) then
      call setup()
      call fused_start(scheme_musl, particles, grid, seg, totals)
      call fused_step(scheme_musl, particles, grid, seg, dt, youngs, totals)
      f1 = 0.25_dp
      p1 = 5.25_dp + dt*f1
      a1 = f1/m
      v1 = p1/m
      v_expected = [1.0_dp + dt*0.25_dp*a1, 2.0_dp + dt*0.75_dp*a1]
      x_expected = [0.5_dp + dt*0.25_dp*v1, 1.5_dp + dt*0.75_dp*v1]
      v1 = m*(0.25_dp*v_expected(1) + 0.75_dp*v_expected(2))/m
      de = dt*v1/dx
      s_expected = [0.5_dp, -1.0_dp] + youngs*de
      j_expected = 1.0_dp + de
      call compare('musl')
      call setup_generic()
      call scheme_step(scheme_musl, bar, cache, particles, grid, dt, youngs, 0.0_dp, totals)
      call compare('generic musl')
      call compare_totals('generic musl')
   end if

   ! A particle that leaves the grid in a step is named by that step: velocities 0 and 20 give
   ! p_1 = 3 (3/4 * 20) = 45, v_1 = 15 (and a little from the force), so particle 2 moves to
   ! 1.5 + 0.1 * 3/4 * 15 = 2.6 > 2 (past the last node) while particle 1 stays inside.
   if (t%case('particle_leaving_the_grid')) then
      call setup_generic()
      particles%v = [0.0_dp, 20.0_dp]
      call scheme_step(scheme_usl, bar, cache, particles, grid, dt, youngs, 0.0_dp, totals)
      call t%check('generic usl: the particle that left the grid in this step is named', totals%outside == 2)
      call t%check('generic usl: ... and it is past the last node', particles%x(2) > dx .and. particles%x(1) < dx)
   end if
   call t%finish()

contains

   subroutine setup()
      type(error_t), allocatable :: error
      call particles_init(particles, 1, 2, dx, 3.0_dp, error)
      call grid_init(grid, 1, dx, particles%mass, error, fixed=[0])
      particles%v = [1.0_dp, 2.0_dp]
      particles%stress = [0.5_dp, -1.0_dp]
      stress = particles%stress
      call t%check('hand set-up: masses 3, volumes 1, positions 0.5 and 1.5', particles%mass == m .and. &
                   particles%volume0 == 1.0_dp .and. all(particles%x == [0.5_dp, 1.5_dp]))
   end subroutine setup

   !> The same set-up on the generic path: per-particle masses and volumes, no element shares.
   subroutine setup_generic()
      type(error_t), allocatable :: error
      call particles_init(particles, 1, 2, dx, 3.0_dp, error)
      call per_particle_data(particles, error)
      call grid_init(grid, 1, dx, particles%mass, error, fixed=[0], element_shares=.false.)
      particles%v = [1.0_dp, 2.0_dp]
      particles%stress = [0.5_dp, -1.0_dp]
      call t%check('generic hand set-up: masses 3, volumes 1', all(particles%mass_of == m) .and. &
                   all(particles%volume0_of == 1.0_dp))
   end subroutine setup_generic

   !> The step's totals from the hand values: sum m (x - X), kinetic energy, the largest move in cells
   !> and its particle (particle 2: 3/4 of the nodal velocity against 1/4), no particle outside.
   subroutine compare_totals(scheme)
      character(len=*), intent(in) :: scheme
      real(dp), parameter :: x_start(2) = [0.5_dp, 1.5_dp]
      call t%check_close(scheme//' total sum m (x - X)', totals%displacement, sum(m*(x_expected - x_start)), &
                         rtol=1.0e-13_dp)
      call t%check_close(scheme//' total kinetic energy', totals%kinetic_energy, sum(0.5_dp*m*v_expected**2), &
                         rtol=1.0e-14_dp)
      call t%check_close(scheme//' largest move in cells', totals%max_cell_move, &
                         maxval(abs(x_expected - x_start))/dx, rtol=1.0e-13_dp)
      call t%check(scheme//' the particle that moved furthest', totals%furthest == 2)
      call t%check(scheme//' no particle outside', totals%outside == 0)
   end subroutine compare_totals

   subroutine compare(scheme)
      character(len=*), intent(in) :: scheme
      integer :: p
      character(len=1) :: c
      do p = 1, 2
         write (c, '(i1)') p
         call t%check_close(scheme//' velocity '//c, particles%v(p), v_expected(p), rtol=1.0e-14_dp)
         call t%check_close(scheme//' position '//c, particles%x(p), x_expected(p), rtol=1.0e-14_dp)
         call t%check_close(scheme//' stress '//c, particles%stress(p), s_expected(p), rtol=1.0e-13_dp)
         call t%check_close(scheme//' volume ratio '//c, particles%volume_ratio(p), j_expected(p), rtol=1.0e-14_dp)
      end do
   end subroutine compare
end program test_scheme_step
