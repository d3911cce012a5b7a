!> What a sweep file holds of its cases (issue 24): a case a guard stopped has no result (max_error
!> NaN, the error reached before the stop in its own column, equal to a single run's), a case not
!> timed has no run time; a sweep continued from its file (resume) equals an uninterrupted one bit for
!> bit in every column but the timings, histories included, and another sweep's file is refused;
!> /cases carries the columns of the scene's own variables, in a merged file too.
program test_sweep_file
   use, intrinsic :: ieee_arithmetic, only: ieee_is_nan, ieee_is_finite
   use mpm_kinds, only: dp, i8
   use mpm_errors, only: error_t
   use mpm_config, only: config_t
   use mpm_simulation, only: run_result_t, run_simulation
   use mpm_sweep, only: sweep_t, sweep_case_t, read_sweep, run_sweep, case_config, cases_done
   use mpm_sweep_output, only: write_sweep_file, merge_sweep_files, resume_sweep
   use mpm_hdf5, only: h5_read_real, h5_read_int, h5_read_string, h5_exists
   use mpm_diagnostics, only: status_ok, status_not_run
   use mpm_testing, only: tester_t, tester, scratch_dir
   implicit none
   type(tester_t) :: t
   type(error_t), allocatable :: error
   character(len=:), allocatable :: dir

   t = tester('test_sweep_file')
   dir = scratch_dir('sweep_results')
   if (t%case('stopped_cases_have_no_value')) call stopped_cases_have_no_value()
   if (t%case('resume_equals_uninterrupted')) call resume_equals_uninterrupted()
   if (t%case('scene_columns_only')) call scene_columns_only()
   if (t%case('integrator_columns')) call integrator_columns()
   call t%finish()

contains

   !> Cases stopped by the energy guard (dt = 2.5 dx/c) beside completed ones.
   subroutine stopped_cases_have_no_value()
      type(sweep_t) :: s
      type(config_t) :: config
      type(run_result_t) :: single
      real(dp), allocatable :: max_error(:), before(:)
      logical :: stopped_ok, completed_ok, same_as_single
      integer :: i
      call write_input(dir//'/stopped.nml', "&output file='"//dir//"/stopped.h5' /", &
                       "&sweep elements=5, 10, dt_fraction=0.1, 2.5, min_time=0 /")
      call read_sweep(dir//'/stopped.nml', s, error, 0, 0, 1)
      call t%check('stopped sweep read', .not. allocated(error))
      if (allocated(error)) return
      call run_sweep(s)
      associate (c => s%cases)
         call t%check('the sweep has completed and stopped cases', any(c%status == status_ok) .and. &
                      any(c%status /= status_ok))
         stopped_ok = all(pack(ieee_is_nan(c%max_error) .and. ieee_is_nan(c%relative_error) .and. &
                               ieee_is_finite(c%error_before_stop) .and. c%error_before_stop > 0 .and. &
                               ieee_is_finite(c%relative_error_before_stop), c%status /= status_ok))
         completed_ok = all(pack(ieee_is_finite(c%max_error) .and. c%max_error > 0 .and. &
                                 ieee_is_nan(c%error_before_stop) .and. ieee_is_nan(c%relative_error_before_stop), &
                                 c%status == status_ok))
         call t%check('a stopped case: max_error and relative_error NaN, the error before the stop finite', stopped_ok)
         call t%check('a completed case: max_error finite, no error before a stop', completed_ok)
         call t%check('min_time = 0: no case timed (run_time and its spread NaN, repeats 0)', &
                      all(ieee_is_nan(c%run_time) .and. ieee_is_nan(c%run_time_spread) .and. c%repeats == 0))
      end associate
      same_as_single = .true.
      do i = 1, size(s%cases)
         config = case_config(s, s%cases(i))
         call run_simulation(config, single, error, record_history=.false.)
         if (s%cases(i)%status == status_ok) then
            same_as_single = same_as_single .and. single%max_error == s%cases(i)%max_error
         else
            same_as_single = same_as_single .and. single%max_error == s%cases(i)%error_before_stop .and. &
                             single%status == s%cases(i)%status
         end if
      end do
      call t%check('each case''s error (before the stop or not) is a single run''s', same_as_single)
      call write_sweep_file(dir//'/stopped.h5', s, error)
      call t%check('stopped sweep written', .not. allocated(error))
      call h5_read_real(dir//'/stopped.h5', '/cases/max_error', max_error, error)
      call h5_read_real(dir//'/stopped.h5', '/cases/error_before_stop', before, error)
      call t%check('the file: NaN max_error exactly where a guard stopped the case', .not. allocated(error))
      if (allocated(error)) return
      call t%check('the file: NaN max_error exactly where a guard stopped the case', &
                   all(ieee_is_nan(max_error) .eqv. s%cases%status /= status_ok) .and. &
                   all(ieee_is_nan(before) .eqv. s%cases%status == status_ok))
   end subroutine stopped_cases_have_no_value

   !> A sweep of 12 cases with histories; the file of a run in which 5 of them (two stopped by a
   !> guard among them... or not) were not run, resumed, equals the uninterrupted run's file.
   subroutine resume_equals_uninterrupted()
      type(sweep_t) :: whole, part, again, other
      integer, parameter :: dropped(*) = [1, 4, 5, 9, 12]
      integer :: i
      call write_input(dir//'/resume.nml', "&output file='"//dir//"/resume.h5' /", &
                       "&sweep schemes='usf','usl', elements=3, 6, dt_fraction=0.1, 0.5, 2.4, min_time=0, "// &
                       "histories=.true. /")
      call read_sweep(dir//'/resume.nml', whole, error, 0, 0, 2)
      call t%check('resume sweep read', .not. allocated(error))
      if (allocated(error)) return
      call run_sweep(whole)
      call write_sweep_file(dir//'/whole.h5', whole, error)
      call t%check('uninterrupted sweep written', .not. allocated(error))
      ! the file an interrupted run leaves: the dropped cases back to not run
      call read_sweep(dir//'/resume.nml', part, error, 0, 0, 1)
      call run_sweep(part)
      call t%check('the cases dropped include a stopped one and a completed one', &
                   any(part%cases(dropped)%status /= status_ok) .and. any(part%cases(dropped)%status == status_ok))
      do i = 1, size(dropped)
         associate (c => part%cases(dropped(i)))
            c = sweep_case_t(index=c%index, steps=c%steps, dt=c%dt, particles=c%particles)
         end associate
      end do
      call write_sweep_file(dir//'/resume.h5', part, error)
      ! a fresh read of the same input continues it
      call read_sweep(dir//'/resume.nml', again, error, 0, 0, 2)
      call resume_sweep(dir//'/resume.h5', again, error)
      call t%check('the sweep''s own file is resumed', .not. allocated(error))
      if (allocated(error)) then
         print '(a)', error%message
         return
      end if
      call t%check('resume: the 7 cases that ran are kept, 5 left to run', cases_done(again%cases) == 7 .and. &
                   all(again%cases(dropped)%status == status_not_run))
      call run_sweep(again)
      call write_sweep_file(dir//'/resume.h5', again, error)
      call t%check('resumed sweep written', .not. allocated(error))
      call compare_files(dir//'/whole.h5', dir//'/resume.h5')
      ! another sweep's file is refused, naming it
      call write_input(dir//'/other.nml', "&output file='"//dir//"/resume.h5' /", &
                       "&sweep schemes='usf','usl', elements=3, 7, dt_fraction=0.1, 0.5, 2.4, min_time=0, "// &
                       "histories=.true. /")
      call read_sweep(dir//'/other.nml', other, error, 0, 0, 1)
      call resume_sweep(dir//'/resume.h5', other, error)
      call t%check('another sweep''s file is refused', allocated(error))
      if (allocated(error)) call t%check_contains('... naming the file', error%message, "resume: '"//dir// &
                                                  "/resume.h5' holds another sweep: its &sweep group differs")
   end subroutine resume_equals_uninterrupted

   !> Every column but the timings identical bit for bit (NaN as NaN), and every history.
   subroutine compare_files(a, b)
      character(len=*), intent(in) :: a, b
      character(len=*), parameter :: reals(*) = [character(len=28) :: 'dt_fraction', 'dt', 'max_error', &
         'relative_error', 'error_before_stop', 'relative_error_before_stop', 'max_energy_ratio', &
         'final_energy_ratio', 'min_volume_ratio', 'max_cell_move', 'min_node_mass_ratio', 'trip_time']
      character(len=*), parameter :: ints(*) = [character(len=28) :: 'index', 'elements', 'particles', 'steps', &
                                                'status', 'trip_step']
      character(len=*), parameter :: texts(*) = [character(len=28) :: 'scheme', 'status_name', 'message']
      character(len=*), parameter :: fields(*) = [character(len=16) :: 'time', 'ucm', 'ucm_exact', &
                                                  'kinetic_energy', 'strain_energy']
      real(dp), allocatable :: ra(:), rb(:)
      integer, allocatable :: ia(:), ib(:)
      character(len=1024), allocatable :: sa(:), sb(:)
      character(len=6) :: name
      logical :: same
      integer :: k, i
      do k = 1, size(reals)
         call h5_read_real(a, '/cases/'//trim(reals(k)), ra, error)
         call h5_read_real(b, '/cases/'//trim(reals(k)), rb, error)
         call t%check('resumed = uninterrupted, bit for bit: '//trim(reals(k)), .not. allocated(error) .and. &
                      size(ra) == size(rb) .and. all(transfer(ra, 1_i8, size(ra)) == transfer(rb, 1_i8, size(rb))))
      end do
      do k = 1, size(ints)
         call h5_read_int(a, '/cases/'//trim(ints(k)), ia, error)
         call h5_read_int(b, '/cases/'//trim(ints(k)), ib, error)
         call t%check('resumed = uninterrupted: '//trim(ints(k)), .not. allocated(error) .and. &
                      size(ia) == size(ib) .and. all(ia == ib))
      end do
      do k = 1, size(texts)
         call h5_read_string(a, '/cases/'//trim(texts(k)), 1024, sa, error)
         call h5_read_string(b, '/cases/'//trim(texts(k)), 1024, sb, error)
         call t%check('resumed = uninterrupted: '//trim(texts(k)), .not. allocated(error) .and. &
                      size(sa) == size(sb) .and. all(sa == sb))
      end do
      same = .true.
      do i = 1, 12
         write (name, '(i6.6)') i
         do k = 1, size(fields)
            call h5_read_real(a, '/histories/'//name//'/'//trim(fields(k)), ra, error)
            call h5_read_real(b, '/histories/'//name//'/'//trim(fields(k)), rb, error)
            same = same .and. .not. allocated(error)
            if (allocated(error)) exit
            same = same .and. size(ra) == size(rb)
            if (same) same = all(transfer(ra, 1_i8, size(ra)) == transfer(rb, 1_i8, size(rb)))
         end do
      end do
      call t%check('resumed = uninterrupted: the 12 histories, bit for bit', same)
   end subroutine compare_files

   !> An impact sweep's /cases has gap and contact but no gravity, mode or velocity_amplitude; its
   !> shards merge into a file with the same columns.
   subroutine scene_columns_only()
      type(sweep_t) :: shard
      character(len=1024) :: files(2)
      character(len=*), parameter :: impact_columns(*) = [character(len=20) :: 'gap', 'contact', 'elements', 'scheme']
      character(len=*), parameter :: bar_columns(*) = [character(len=20) :: 'gravity', 'mode', 'velocity_amplitude', &
                                                       'amplitude', 'drive_velocity']
      character(len=*), parameter :: implicit_columns(*) = [character(len=20) :: 'mass', 'newton_tolerance', &
                                                            'load_steps', 'ghost_penalty', 'yield_stress', &
                                                            'hardening_modulus']
      integer :: i, k
      call write_input(dir//'/impact.nml', "&scene kind='impact', lengths=1.0, 1.0, youngs_moduli=200.0e9, "// &
                       "200.0e9, densities=7800.0, 7800.0, velocities=1.0, -1.0, gap=0.0 / &discretisation "// &
                       "elements=8 / &run periods=0.25 / &output file='"//dir//"/impact.h5' /", &
                       "&sweep contact='frictionless','none', elements=8, 12, min_time=0 /")
      do i = 1, 2
         call read_sweep(dir//'/impact.nml', shard, error, i, 2, 1)
         call t%check('impact sweep shard read', .not. allocated(error))
         if (allocated(error)) then
            print '(a)', error%message
            return
         end if
         call run_sweep(shard)
         write (files(i), '(a,i0,a)') dir//'/impact_shard', i, '.h5'
         call write_sweep_file(trim(files(i)), shard, error)
      end do
      call merge_sweep_files(dir//'/impact.h5', files, error)
      call t%check('impact shards merged', .not. allocated(error))
      if (allocated(error)) then
         print '(a)', error%message
         return
      end if
      do k = 1, size(impact_columns)
         call t%check('impact: /cases/'//trim(impact_columns(k))//' in a shard and in the merged file', &
                      h5_exists(trim(files(1)), '/cases/'//trim(impact_columns(k))) .and. &
                      h5_exists(dir//'/impact.h5', '/cases/'//trim(impact_columns(k))))
      end do
      do k = 1, size(bar_columns)
         call t%check('impact: no /cases/'//trim(bar_columns(k))//' (another scene''s variable)', &
                      .not. h5_exists(trim(files(1)), '/cases/'//trim(bar_columns(k))) .and. &
                      .not. h5_exists(dir//'/impact.h5', '/cases/'//trim(bar_columns(k))))
      end do
      do k = 1, size(implicit_columns)
         call t%check('explicit hencky sweep: no /cases/'//trim(implicit_columns(k))//' (another integrator''s '// &
                      'or law''s variable)', .not. h5_exists(trim(files(1)), '/cases/'//trim(implicit_columns(k))) &
                      .and. .not. h5_exists(dir//'/impact.h5', '/cases/'//trim(implicit_columns(k))))
      end do
   end subroutine scene_columns_only

   !> A sweep over the integrators has the columns of the variables its implicit cases use (mass,
   !> newton_tolerance, ghost_penalty), not quasi_static's load_steps or the elastoplastic law's.
   subroutine integrator_columns()
      type(sweep_t) :: s
      character(len=*), parameter :: used(*) = [character(len=20) :: 'integrator', 'mass', 'newton_tolerance', &
                                                'ghost_penalty', 'law']
      character(len=*), parameter :: unused(*) = [character(len=20) :: 'load_steps', 'yield_stress', &
                                                  'hardening_modulus']
      integer :: k
      call write_input(dir//'/integrators.nml', "&discretisation elements=8 / &run periods=0.25 / &output file='"// &
                       dir//"/integrators.h5' /", "&sweep integrator='explicit','implicit', min_time=0 /")
      call read_sweep(dir//'/integrators.nml', s, error, 0, 0, 1)
      call t%check('integrator sweep read', .not. allocated(error))
      if (allocated(error)) then
         print '(a)', error%message
         return
      end if
      call run_sweep(s)
      call write_sweep_file(dir//'/integrators.h5', s, error)
      call t%check('integrator sweep written', .not. allocated(error))
      do k = 1, size(used)
         call t%check('integrator sweep: /cases/'//trim(used(k)), h5_exists(dir//'/integrators.h5', &
                                                                           '/cases/'//trim(used(k))))
      end do
      do k = 1, size(unused)
         call t%check('integrator sweep: no /cases/'//trim(unused(k)), .not. h5_exists(dir//'/integrators.h5', &
                                                                                    '/cases/'//trim(unused(k))))
      end do
   end subroutine integrator_columns
   !> A namelist file of two lines.
   subroutine write_input(path, first, second)
      character(len=*), intent(in) :: path, first, second
      integer :: unit
      open (newunit=unit, file=path, status='replace', action='write')
      write (unit, '(a)') first, second
      close (unit)
   end subroutine write_input
end program test_sweep_file
