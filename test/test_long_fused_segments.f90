!> Second tier (`bash test/run_tests.sh --all`; about 3.5 minutes of CPU): the fused kernels on large
!> runs cut into segments, for every scheme (USF, USL, MUSL) and wide shape (uGIMP, cpGIMP, quadratic
!> and cubic B-splines): 120,000 particles (30,000 elements x 4) for 960 steps at v0 = 50 m/s, so that
!> particles cross cells and segment boundaries many times. Each run agrees with the generic path (same
!> status and steps, u_cm to round-off, kinetic energy to 1e-10: mpm_testing's check_paths_agree) and
!> gives bit for bit the same u_cm and energy histories on 1 and 2 threads. test_fused_shapes runs the
!> same checks on the smallest segmented run for 50 steps.
program test_long_fused_segments
   use mpm_kinds, only: dp
   use mpm_testing, only: tester_t, check_fused_run
   implicit none
   type(tester_t) :: t
   character(len=4), parameter :: schemes(3) = ['usf ', 'usl ', 'musl']
   character(len=8), parameter :: shapes(4) = ['ugimp   ', 'cpgimp  ', 'bspline2', 'bspline3']
   integer :: i, j
   t%name = 'test_long_fused_segments'
   do j = 1, size(shapes)
      do i = 1, size(schemes)
         call check_fused_run(t, trim(schemes(i)), trim(shapes(j)), 30000, 4, 0.5_dp, 50.0_dp, 0.004_dp, segments=.true.)
      end do
   end do
   call t%finish()
end program test_long_fused_segments
