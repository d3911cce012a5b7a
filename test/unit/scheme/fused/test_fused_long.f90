!> Second tier (`bash test/run_tests.sh --all`; about 3.5 minutes of CPU): the fused kernels on large
!> runs cut into segments, for every scheme (USF, USL, MUSL) and wide shape (uGIMP, cpGIMP, quadratic
!> and cubic B-splines): 120,000 particles (30,000 elements x 4) for 960 steps at v0 = 50 m/s, so that
!> particles cross cells and segment boundaries many times. Each run agrees with the generic path (same
!> status and steps, u_cm to round-off, kinetic energy to 1e-10: mpm_testing_runs' check_paths_agree) and
!> gives bit for bit the same u_cm and energy histories on 1 and 2 threads. test_fused_shapes runs the
!> same checks on the smallest segmented run for 50 steps.
!> Then two soft bars on their own velocity fields (impact, frictionless contact; USL and MUSL) on a grid
!> of 60,000 nodes per field: their fields are assembled and solved in node chunks on threads, only
!> on the nodes each body holds values at (fused_step's active_nodes); the bars cross cells and meet.
program test_fused_long
   use mpm_kinds, only: dp
   use mpm_config, only: config_t, new_config
   use mpm_testing, only: tester_t, tester
   use mpm_testing_runs, only: check_fused_run, check_fused_config, set_values
   implicit none
   type(tester_t) :: t
   type(config_t) :: config
   character(len=4), parameter :: schemes(3) = ['usf ', 'usl ', 'musl']
   character(len=8), parameter :: shapes(4) = ['ugimp   ', 'cpgimp  ', 'bspline2', 'bspline3']
   integer :: i, j
   t = tester('test_fused_long')
   if (t%case('wide_shapes_120000_particles', long=.true.)) then
      do j = 1, size(shapes)
         do i = 1, size(schemes)
            call check_fused_run(t, trim(schemes(i)), trim(shapes(j)), 30000, 4, 0.5_dp, 50.0_dp, 0.004_dp, segments=.true.)
         end do
      end do
   end if
   if (t%case('impact_60000_nodes', long=.true.)) then
      do i = 2, size(schemes)
         config = new_config()
         call set_values(config, ["scene.kind='impact'"])
         config%scheme = trim(schemes(i))
         call set_values(config, ['scene.lengths=1.0, 1.0'])
         call set_values(config, ['scene.youngs_moduli=1.0e6, 1.0e6'])
         call set_values(config, ['scene.densities=1000.0, 1000.0'])
         call set_values(config, ['scene.velocities=1.4, 0.6'])
         call set_values(config, ['scene.gap=1.0e-4']) ! (3 cells: they meet at step 593 of 1793; bar 1 moves 16 cells)
         call set_values(config, ["scene.contact='frictionless'"])
         config%elements = 60000
         config%particles_per_element = 2
         config%dt_fraction = 0.2_dp
         config%periods = 0.004_dp
         call check_fused_config(t, trim(schemes(i))//' impact, soft bars on 60,000 nodes per field: ', config, &
                                 segments=.true.)
      end do
   end if
   call t%finish()
end program test_fused_long
