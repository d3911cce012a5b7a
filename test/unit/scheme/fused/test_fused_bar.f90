!> The generic path (shape cache, per-particle data, mpm_scheme_usf/usl/musl over mpm_operations)
!> against the fused kernels of the paper's bar: same steps and status, and u_cm histories equal to
!> round-off (mpm_testing_runs' check_paths_agree: 1e-12 of the exact amplitude plus two ulps of the bar
!> length per particle; 3 elements x 4 particles: spacing(25)/12 = 3e-16 m = 1.5e-12 of 2e-4 m).
program test_fused_bar
   use mpm_kinds, only: dp
   use mpm_errors, only: error_t
   use mpm_config, only: config_t, resolve_config
   use mpm_simulation, only: run_result_t, run_simulation
   use mpm_testing, only: tester_t, tester
   use mpm_testing_runs, only: check_fused_run
   use omp_lib, only: omp_set_num_threads
   implicit none
   type(tester_t) :: t
   character(len=4), parameter :: schemes(3) = ['usf ', 'usl ', 'musl']
   integer :: i

   t = tester('test_fused_bar')
   if (t%case('fused_bar')) then
      do i = 1, 3
         call check_fused_run(t, trim(schemes(i)), 'linear', 20, 1, 0.1_dp, 0.1_dp, 2.0_dp)
         call check_fused_run(t, trim(schemes(i)), 'linear', 3, 4, 0.4_dp, 0.1_dp, 2.0_dp)
         call check_fused_run(t, trim(schemes(i)), 'linear', 10, 7, 0.45_dp, 0.1_dp, 2.0_dp)
         call check_fused_run(t, trim(schemes(i)), 'linear', 50, 2, 0.25_dp, 0.1_dp, 2.0_dp)
         ! the free end crosses into the empty margin (v0/omega = 0.25 dx)
         call check_fused_run(t, trim(schemes(i)), 'linear', 200, 4, 0.5_dp, 10.0_dp, 0.3_dp)
      end do
   end if
   if (t%case('threads_identical')) call threads_identical()
   call t%finish()

contains

   !> The generic path gives the same bits on 1 and 2 threads (a large run: above the fused kernels'
   !> thresholds for threaded passes and node loops).
   subroutine threads_identical()
      type(run_result_t) :: one, two
      type(config_t) :: config
      type(error_t), allocatable :: error
      config%scheme = 'usl'
      config%elements = 60000
      config%particles_per_element = 4
      config%end_time = 30*0.5_dp*(25.0_dp/60000)/sqrt(200.0e9_dp/7800.0_dp)
      config%dt_fraction = 0.5_dp
      config%kernels = 'generic'
      call resolve_config(config)
      call omp_set_num_threads(1)
      call run_simulation(config, one, error, record_history=.true.)
      call omp_set_num_threads(2)
      call run_simulation(config, two, error, record_history=.true.)
      call t%check('generic path, 240,000 particles: 1 and 2 threads give the same u_cm and energy histories', &
                   one%steps_done == 30 .and. two%steps_done == 30 .and. &
                   all(one%history%ucm == two%history%ucm) .and. &
                   all(one%history%kinetic_energy == two%history%kinetic_energy))
   end subroutine threads_identical
end program test_fused_bar
