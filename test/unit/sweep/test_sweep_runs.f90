!> Sweeps: per-case errors equal single runs of the same cases; 1 and 2 threads give identical
!> errors; shards merged give the unsharded table; bad sweep input is refused.
program test_sweep_runs
   use mpm_kinds, only: dp
   use mpm_errors, only: error_t
   use mpm_config, only: config_t
   use mpm_simulation, only: run_result_t, run_simulation
   use mpm_sweep, only: sweep_t, sweep_case_t, read_sweep, run_sweep, case_config, case_weights
   use mpm_progress, only: remaining_time
   use mpm_sort, only: sort_order, relative_spread
   use mpm_sweep_output, only: write_sweep_file, merge_sweep_files
   use mpm_hdf5, only: h5_read_real, h5_read_int, h5_read_string
   use mpm_diagnostics, only: status_ok
   use mpm_testing, only: tester_t, tester, scratch_dir
   implicit none
   type(tester_t) :: t
   type(sweep_t) :: one_thread, two_threads, shard
   type(error_t), allocatable :: error
   character(len=:), allocatable :: dir, input
   integer :: i, unit
   character(len=1024) :: shard_files(3)

   t = tester('test_sweep_runs')
   dir = scratch_dir('sweep')
   input = dir//'/sweep.nml'
   open (newunit=unit, file=input, status='replace', action='write')
   write (unit, '(a)') "&output file='"//dir//"/sweep.h5' /", &
      "&sweep schemes='usf','usl','musl', elements=1,3,10, particles_per_element=1,4, dt_fractions=0.05,0.3, min_time=0.0 /"
   close (unit)

   if (t%case('threads_single_runs_and_shards')) then
      call read_sweep(input, one_thread, error, 0, 0, 1)
      call t%check('sweep read', .not. allocated(error))
      if (allocated(error)) print '(a)', error%message
      call t%check('3 x 3 x 2 x 2 = 36 cases', size(one_thread%cases) == 36 .and. one_thread%total_cases == 36)
      call run_sweep(one_thread)
      call t%check('every case completed', all(one_thread%cases%status == status_ok))

      ! Each case equals a single run of the same configuration, bit for bit.
      do i = 1, size(one_thread%cases), 5
         call compare_with_single_run(one_thread%cases(i)%index)
      end do

      call read_sweep(input, two_threads, error, 0, 0, 2)
      call run_sweep(two_threads)
      call t%check('2 threads used', two_threads%threads_used == 2)
      call t%check('1 and 2 threads: identical errors', all(one_thread%cases%max_error == two_threads%cases%max_error))
      call t%check('1 and 2 threads: identical steps', all(one_thread%cases%steps == two_threads%cases%steps))
      call write_sweep_file(dir//'/whole.h5', two_threads, error)
      call t%check('whole sweep written', .not. allocated(error))

      ! Three shards, written separately and merged in a scrambled order.
      do i = 1, 3
         call read_sweep(input, shard, error, i, 3, 1)
         call run_sweep(shard)
         write (shard_files(i), '(a,i0,a)') dir//'/shard', i, '.h5'
         call write_sweep_file(trim(shard_files(i)), shard, error)
         call t%check('shard written', .not. allocated(error))
      end do
      call merge_sweep_files(dir//'/merged.h5', shard_files([3, 1, 2]), error)
      call t%check('shards merged', .not. allocated(error))
      if (allocated(error)) print '(a)', error%message
      call compare_files(dir//'/whole.h5', dir//'/merged.h5')
      call merge_sweep_files(dir//'/bad.h5', shard_files([1, 2]), error)
      call t%check('merge refuses a missing shard', allocated(error))
      call merge_sweep_files(dir//'/bad.h5', shard_files([1, 1, 2]), error)
      call t%check('merge refuses a repeated shard', allocated(error))
   end if

   if (t%case('unstable_messages')) call unstable_messages()
   if (t%case('list_names')) call list_names()
   if (t%case('progress_estimate')) call progress_estimate()
   if (t%case('timing_spread')) call timing_spread()

   if (t%case('bad_sweeps')) then
      call bad_sweep("&sweep elements=3, 0 /", 'elements(2)')
      call bad_sweep("&sweep schemes='usf', 'fls' /", 'schemes(2)')
      call bad_sweep("&sweep dt_fractions=0.1, NaN /", 'dt_fractions(2)')
      call bad_sweep("&sweep shard=4, shards=3 /", 'shard')
      call bad_sweep("&sweep elements=3, , 5 /", 'gap')
      call bad_sweep("&sweep min_time=-1.0 /", 'min_time')
      call bad_sweep("&sweep timing_threads=0 /", 'timing_threads')
      call bad_sweep("&sweep particle_per_element=3 /", 'particle_per_element')
      call bad_sweep("&sweep elements= /", 'elements is an empty list')
      call bad_sweep("&run end_time=2.0e-4 / &sweep elements=3, 1000000000, particles_per_element=2 /", &
                     'memory available')
      call bad_sweep("&sweep elements=, dt_fractions=0.1 /", 'elements is an empty list')
      call bad_sweep("&sweep scheme='usf', schemes='usl' /", "list 'scheme' is given twice (as 'schemes'")
      call bad_sweep("&sweep dt_fraction=0.1, 0, elements=2 /", 'dt_fraction(2)')
   end if
   call t%finish()

contains

   !> Many cases stopped by guards at once on 2 threads: the same statuses and the same, intact
   !> messages as on 1 thread.
   subroutine unstable_messages()
      type(sweep_t) :: serial, parallel
      integer :: u, k
      logical :: same
      open (newunit=u, file=dir//'/unstable.nml', status='replace', action='write')
      write (u, '(a)') "&output file='"//dir//"/unstable.h5' /", &
         "&sweep schemes='usl','usf', elements=5,10,20, particles_per_element=1,2,3,4, "// &
         "dt_fractions=1.0,1.5,2.2,2.4,2.6, min_time=0.0 /"
      close (u)
      call read_sweep(dir//'/unstable.nml', serial, error, 0, 0, 1)
      call run_sweep(serial)
      call read_sweep(dir//'/unstable.nml', parallel, error, 0, 0, 2)
      call run_sweep(parallel)
      call t%check('unstable sweep: many cases stopped', count(serial%cases%status /= status_ok) > 50)
      call t%check('unstable sweep: same statuses on 1 and 2 threads', all(serial%cases%status == parallel%cases%status))
      same = .true.
      do k = 1, size(serial%cases)
         if (serial%cases(k)%status == status_ok) cycle
         if (serial%cases(k)%message /= parallel%cases(k)%message) same = .false.
         if (index(parallel%cases(k)%message, ' tripped at step ') == 0 .or. &
             index(parallel%cases(k)%message, ' of '//itoa(parallel%cases(k)%steps)//' (t = ') == 0) same = .false.
      end do
      call t%check('unstable sweep: intact, identical messages on 1 and 2 threads', same)
   end subroutine unstable_messages

   function itoa(i) result(text)
      integer, intent(in) :: i
      character(len=:), allocatable :: text
      character(len=12) :: buffer
      write (buffer, '(i0)') i
      text = trim(buffer)
   end function itoa

   subroutine compare_with_single_run(index)
      integer, intent(in) :: index
      type(config_t) :: config
      type(run_result_t) :: r
      type(error_t), allocatable :: run_error
      config = case_config(one_thread, one_thread%cases(index))
      call run_simulation(config, r, run_error, record_history=.false.)
      call t%check('case equals single run (max error)', r%max_error == one_thread%cases(index)%max_error)
      call t%check('case equals single run (steps)', r%steps == one_thread%cases(index)%steps)
   end subroutine compare_with_single_run

   !> Every deterministic column of the two files is identical (run times are measurements).
   subroutine compare_files(a, b)
      character(len=*), intent(in) :: a, b
      character(len=*), parameter :: real_columns(*) = [character(len=20) :: 'dt_fraction', 'dt', 'max_error', &
                                                        'relative_error', 'max_energy_ratio', 'final_energy_ratio']
      character(len=*), parameter :: int_columns(*) = [character(len=24) :: 'index', 'elements', &
                                                       'particles_per_element', 'steps', 'status', 'particles']
      real(dp), allocatable :: ra(:), rb(:)
      integer, allocatable :: ia(:), ib(:)
      character(len=8), allocatable :: sa(:), sb(:)
      integer :: k
      do k = 1, size(real_columns)
         call h5_read_real(a, '/cases/'//trim(real_columns(k)), ra, error)
         call h5_read_real(b, '/cases/'//trim(real_columns(k)), rb, error)
         call t%check('merged = unsharded: '//trim(real_columns(k)), size(ra) == size(rb) .and. all(ra == rb))
      end do
      do k = 1, size(int_columns)
         call h5_read_int(a, '/cases/'//trim(int_columns(k)), ia, error)
         call h5_read_int(b, '/cases/'//trim(int_columns(k)), ib, error)
         call t%check('merged = unsharded: '//trim(int_columns(k)), size(ia) == size(ib) .and. all(ia == ib))
      end do
      call h5_read_string(a, '/cases/scheme', 8, sa, error)
      call h5_read_string(b, '/cases/scheme', 8, sb, error)
      call t%check('merged = unsharded: scheme', all(sa == sb))
   end subroutine compare_files

   !> One rule for list names: each list is named as the variable it varies; the former plural
   !> names are aliases giving the same cases, and the echoed &sweep uses the variable's name.
   subroutine list_names()
      type(sweep_t) :: by_name, by_alias
      integer :: u
      open (newunit=u, file=dir//'/names.nml', status='replace', action='write')
      write (u, '(a)') "&sweep scheme='usf','musl', elements=2,5, particles_per_element=1,3, dt_fraction=0.1,0.2, "// &
         "shape='linear','bspline2', transfer='flip','blend', flip_fraction=1.0, mode=1,2, "// &
         "velocity_amplitude=0.1, youngs_modulus=100.0, density=1.0, min_time=0.0 /"
      close (u)
      open (newunit=u, file=dir//'/aliases.nml', status='replace', action='write')
      write (u, '(a)') "&sweep schemes='usf','musl', elements=2,5, particles_per_element=1,3, dt_fractions=0.1,0.2, "// &
         "shapes='linear','bspline2', transfers='flip','blend', flip_fractions=1.0, modes=1,2, "// &
         "velocity_amplitudes=0.1, youngs_moduli=100.0, densities=1.0, min_time=0.0 /"
      close (u)
      call read_sweep(dir//'/names.nml', by_name, error, 0, 0, 1)
      call t%check('lists named as their variables are read', .not. allocated(error))
      if (allocated(error)) print '(a)', error%message
      call read_sweep(dir//'/aliases.nml', by_alias, error, 0, 0, 1)
      call t%check('former list names are read', .not. allocated(error))
      if (allocated(error)) print '(a)', error%message
      if (.not. allocated(by_name%cases) .or. .not. allocated(by_alias%cases)) return
      call t%check('2^7 = 128 cases by either name', size(by_name%cases) == 128 .and. size(by_alias%cases) == 128)
      call t%check('names and aliases: the same namelist echo', &
                   by_name%settings%namelist_text == by_alias%settings%namelist_text)
      if (by_name%settings%namelist_text /= by_alias%settings%namelist_text) &
         print '(a)', by_name%settings%namelist_text, by_alias%settings%namelist_text
      call t%check_contains('the echo names each list as its variable', by_name%settings%namelist_text, &
                            "scheme='usf', 'musl', elements=2, 5, particles_per_element=1, 3, dt_fraction=")
   end subroutine list_names

   !> The progress line's estimate of the time left weighs each case by its cost. By hand: the
   !> weights, and the estimate (elapsed x cost left / cost done). Then with given costs, no clock:
   !> the cases of a real sweep whose cases differ ~250-fold in cost, each taking a fixed set-up time
   !> plus a time proportional to its cost, run in the sweep's order (most expensive first): when half
   !> the cost is done, the estimate is within a factor 2 of the time the rest takes, where the count of
   !> cases would say about ten times too much.
   subroutine progress_estimate()
      type(sweep_t) :: s
      type(sweep_case_t) :: hand(3)
      real(dp), allocatable :: weights(:), finished_at(:)
      integer, allocatable :: order(:)
      real(dp) :: done, estimate, by_count, actual, clock
      !> the model machine: seconds of set-up per case and per particle-step
      real(dp), parameter :: set_up = 2.0e-5_dp, per_cost = 1.0e-8_dp
      integer :: u, k, half
      hand(1) = sweep_case_t(particles=10, steps=100, status=status_ok)
      hand(2) = sweep_case_t(particles=1000, steps=400, status=status_ok)
      hand(3) = sweep_case_t(particles=1000, steps=400, status=1)
      weights = case_weights(hand, 0.0_dp, 0.0_dp)
      call t%check('error pass weights = particles x steps', all(weights == [1000.0_dp, 4.0e5_dp, 4.0e5_dp]))
      weights = case_weights(hand, 1.0e-7_dp, 0.02_dp)
      call t%check('timing pass weights = max(min_time, 3 t), failed cases 0', &
                   all(abs(weights - [0.02_dp, 0.12_dp, 0.0_dp]) < 1.0e-15_dp))
      call t%check('remaining = elapsed x cost left / cost done', &
                   abs(remaining_time(2.0_dp, 1.0_dp, 4.0_dp) - 6.0_dp) < 1.0e-15_dp .and. &
                   remaining_time(2.0_dp, 0.0_dp, 4.0_dp) == 0.0_dp .and. remaining_time(2.0_dp, 4.0_dp, 4.0_dp) == 0.0_dp)

      open (newunit=u, file=dir//'/costs.nml', status='replace', action='write')
      write (u, '(a)') "&sweep elements=25, 50, 100, 200, 400, particles_per_element=1, 2, 4, min_time=0 /"
      close (u)
      call read_sweep(dir//'/costs.nml', s, error, 0, 0, 1)
      call t%check('cost sweep read', .not. allocated(error))
      if (allocated(error)) return
      weights = case_weights(s%cases, 0.0_dp, 0.0_dp)
      call t%check('the cost sweep''s cases differ more than 200-fold in cost', maxval(weights) > 200*minval(weights))
      order = sort_order(-weights)
      allocate (finished_at(size(order)))
      clock = 0.0_dp
      do k = 1, size(order) ! (the model's time from particles x steps, not from the weights under test)
         clock = clock + set_up + per_cost*real(s%cases(order(k))%particles, dp)*s%cases(order(k))%steps
         finished_at(k) = clock
      end do
      done = 0.0_dp
      half = 0
      do k = 1, size(order)
         done = done + weights(order(k))
         if (done >= 0.5_dp*sum(weights)) then
            half = k
            exit
         end if
      end do
      estimate = remaining_time(finished_at(half), done, sum(weights))
      by_count = remaining_time(finished_at(half), real(half, dp), real(size(order), dp))
      actual = finished_at(size(order)) - finished_at(half)
      print '(a,i0,a,i0,3(a,es9.2))', 'progress estimate after ', half, ' of ', size(order), ' cases: ', estimate, &
         ' s (by count ', by_count, ' s); the model machine takes ', actual, ' s'
      call t%check('half the cost done: the estimate is within a factor 2 of the time left', &
                   estimate > 0.5_dp*actual .and. estimate < 2.0_dp*actual)
      call t%check('(the case count alone would be off by more than 3)', by_count > 3.0_dp*actual)
   end subroutine progress_estimate

   !> The timing pass keeps the spread of its repeats: interquartile range over median, by hand;
   !> a timed case either has a spread within 0.2 or was measured in all 3 rounds.
   subroutine timing_spread()
      type(sweep_t) :: s
      integer :: u
      call t%check('spread of 1, 2, 3 (any order) = (2.5 - 1.5) / 2', &
                   abs(relative_spread([3.0_dp, 1.0_dp, 2.0_dp]) - 0.5_dp) < 1.0e-15_dp)
      call t%check('spread of 1, 1, 1, 10 = (3.25 - 1) / 1', &
                   abs(relative_spread([1.0_dp, 10.0_dp, 1.0_dp, 1.0_dp]) - 2.25_dp) < 1.0e-15_dp)
      call t%check('spread of one value = 0', relative_spread([4.0_dp]) == 0.0_dp)
      open (newunit=u, file=dir//'/timed.nml', status='replace', action='write')
      write (u, '(a)') "&sweep elements=3, 10, dt_fraction=0.1, 2.5, min_time=0.002 /"
      close (u)
      call read_sweep(dir//'/timed.nml', s, error, 0, 0, 1)
      call run_sweep(s)
      call t%check('timed cases: spread within 0.2 or 3 rounds measured', all( &
                   pack(s%cases%run_time_spread <= 0.2_dp .or. s%cases%timing_rounds == 3, s%cases%status == status_ok)))
      call t%check('timed cases: at least one round, a positive time', all(pack(s%cases%timing_rounds >= 1 .and. &
                   s%cases%run_time > 0.0_dp, s%cases%status == status_ok)))
      call t%check('cases stopped by a guard are not timed', all(pack(s%cases%timing_rounds == 0, &
                   s%cases%status /= status_ok)) .and. any(s%cases%status /= status_ok))
   end subroutine timing_spread

   subroutine bad_sweep(text, part)
      character(len=*), intent(in) :: text, part
      type(sweep_t) :: s
      integer :: u
      open (newunit=u, file=dir//'/bad.nml', status='replace', action='write')
      write (u, '(a)') text
      close (u)
      call read_sweep(dir//'/bad.nml', s, error, 0, 0, -1)
      call t%check('bad sweep refused: '//text, allocated(error))
      if (allocated(error)) call t%check_contains('bad sweep message: '//text, error%message, part)
   end subroutine bad_sweep
end program test_sweep_runs
