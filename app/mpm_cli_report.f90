!> What the mpm1d command prints: a run's and a sweep's report, their warnings, the dry run, the
!> message of an interrupted sweep, and the end of the program (exit codes). Part of the executable
!> (app/), as the library (src/) prints nothing: it returns errors and results.
module mpm_cli_report
   use, intrinsic :: iso_fortran_env, only: output_unit, error_unit
   use, intrinsic :: ieee_arithmetic, only: ieee_set_flag, ieee_all
   use mpm_kinds, only: dp
   use mpm_strings, only: str, num, plural, readable_numbers
   use mpm_config, only: config_t, config_warnings, stability_limit, write_config_namelist, config_summary
   use mpm_simulation, only: run_result_t, guard_message
   use mpm_diagnostics, only: status_ok, status_not_run
   use mpm_sweep, only: sweep_t, case_config, shard_file, shard_cases, cases_done, cases_timed
   use mpm_files, only: absolute_path
   implicit none
   private
   public :: fail, finish, warn_run, report_config, report_run, warn_rounding, stop_for_guard, sweep_header, &
             report_sweep, interrupted, report_dry_run, report_journal, warn

contains

   !> End with an error: the message on standard error, prefixed 'mpm1d: ', and the exit code. Flushed
   !> before the exit: standard error redirected to a file is buffered, and the message is the one
   !> thing the user must get.
   subroutine fail(message, code)
      character(len=*), intent(in) :: message
      integer, intent(in) :: code
      write (error_unit, '(a)') 'mpm1d: '//message
      flush (error_unit)
      stop code, quiet=.true.
   end subroutine fail

   !> A warning on standard error: 'mpm1d: warning: ' and the text (the run goes on).
   subroutine warn(text)
      character(len=*), intent(in) :: text
      write (error_unit, '(a)') 'mpm1d: warning: '//text
   end subroutine warn

   !> What a resumed sweep took from its journal (standard output): the cases and timings it held, and
   !> a torn last record dropped (a kill in the middle of its write: never read as a result).
   subroutine report_journal(sweep, quiet)
      type(sweep_t), intent(in) :: sweep
      logical, intent(in) :: quiet
      character(len=:), allocatable :: torn
      if (quiet .or. (sweep%journal_records == 0 .and. sweep%journal_torn == 0)) return
      torn = ''
      if (sweep%journal_torn > 0) torn = '; a torn last record of '//str(int(sweep%journal_torn))//' bytes dropped'
      write (output_unit, '(a)') 'from the journal '''//sweep%journal%path//''': '// &
         plural(sweep%journal_cases, 'case')//', '//plural(sweep%journal_records - sweep%journal_cases, 'timing')//torn
      flush (output_unit)
   end subroutine report_journal

   !> Normal end: floating-point flags a run raised on purpose (an energy sum computed again in scaled
   !> form, subnormal intermediates of a far-scaled bar) are no news to the user: no runtime note.
   subroutine finish()
      call ieee_set_flag(ieee_all, .false.)
      stop 0, quiet=.true.
   end subroutine finish

   !> A single run's warnings before it starts (standard error): a time step above the stability
   !> limit, the scene's own warnings (the bar's: a mesh too coarse for its mode).
   subroutine warn_run(config)
      type(config_t), intent(in) :: config
      call warn_stability(config)
      if (len(config_warnings(config)) > 0) write (error_unit, '(a)') 'mpm1d: warning: '//config_warnings(config)
   end subroutine warn_run

   !> The configuration a single run uses, as a namelist, and its one-line summary (flushed: a redirected
   !> log of a long run shows it from the start, and keeps it if the run is killed).
   subroutine report_config(config)
      type(config_t), intent(in) :: config
      write (output_unit, '(a)') '# configuration used:'
      call write_config_namelist(output_unit, config)
      write (output_unit, '(a)') '# '//config_summary(config)
      flush (output_unit)
   end subroutine report_config

   !> What a single run reports on standard output. A run a guard stopped has no result: the error
   !> reached up to the stop is said as such (the file's max_error is NaN, error_before_stop holds it).
   subroutine report_run(config, result)
      type(config_t), intent(in) :: config
      type(run_result_t), intent(in) :: result
      real(dp) :: rate
      character(len=:), allocatable :: what
      rate = real(result%particles, dp)*result%steps_done/max(result%run_time, 1.0e-9_dp)
      what = 'max '
      if (result%status /= status_ok) what = 'no result (stopped by a guard); before the stop: max '
      write (output_unit, '(a)') what//result%error_name//' = '//num(result%max_error)//' '//result%error_unit// &
         ' ('//num(100*result%relative_error, 3)//' % of the exact amplitude '//num(result%ucm_amplitude)//' '// &
         result%error_unit//')'
      if (result%status == status_ok) then
         write (output_unit, '(a)') 'steps '//str(result%steps_done)//' of '//str(result%steps)//', run time '// &
            num(result%run_time, 3)//' s, '//num(rate, 3)//' particle-steps/s'
      else
         ! the step count of the guard's message: the step that tripped it, which did not complete
         write (output_unit, '(a)') 'stopped by a guard at step '//str(result%trip%step)//' of '//str(result%steps)// &
            ' ('//plural(result%steps_done, 'step')//' completed), run time '//num(result%run_time, 3)//' s, '// &
            num(rate, 3)//' particle-steps/s'
      end if
      write (output_unit, '(a)') 'wrote '//absolute_path(trim(config%file))
   end subroutine report_run

   !> An error measured on displacements x_p - X_p (u_cm, the column's, the manufactured solution's):
   !> below a few hundred roundings of x it measures rounding. Named: what sets the scene's amplitude.
   !> (A stress error, the composite bar's and the plastic wave's, is measured on stresses formed from
   !> strain increments, which keep their digits at any amplitude: no warning.)
   subroutine warn_rounding(config, result)
      type(config_t), intent(in) :: config
      type(run_result_t), intent(in) :: result
      character(len=:), allocatable :: raise
      raise = config%scene%amplitude_source()
      if (len(raise) == 0) return
      if (result%ucm_amplitude < 100*spacing(config%length)) write (error_unit, '(a)') 'mpm1d: warning: the '// &
         'exact displacement amplitude '//num(result%ucm_amplitude)//' m is below 100 times the rounding of '// &
         'positions near x = L ('//num(spacing(config%length), 3)//' m): the error measures rounding, not the '// &
         'method; raise '//raise
   end subroutine warn_rounding

   !> A run a guard stopped ends with exit code 1: the guard's message with readable numbers (the file
   !> keeps them in full) and where the history up to the stop is.
   subroutine stop_for_guard(config, result)
      type(config_t), intent(in) :: config
      type(run_result_t), intent(in) :: result
      if (result%status == status_ok) return
      call fail(readable_numbers(guard_message(result%status, result%trip, config), 5)//new_line('a')// &
                'the history up to that step is in '//absolute_path(trim(config%file)), 1)
   end subroutine stop_for_guard

   !> Is the time step above the linear stability limit of the explicit scheme and shape? (The implicit
   !> integrators are unconditionally stable: no limit.)
   logical function above_stability_limit(config)
      type(config_t), intent(in) :: config
      above_stability_limit = trim(config%integrator) == 'explicit' .and. &
                              config%dt_fraction > stability_limit(config%scheme, config%particles_per_element, &
                                                                   config%shape)
   end function above_stability_limit

   !> Warn (standard error) when the time step is above the stability limit of the scheme and shape.
   subroutine warn_stability(config)
      type(config_t), intent(in) :: config
      character(len=:), allocatable :: which
      if (.not. above_stability_limit(config)) return
      which = ''
      if (trim(config%shape) /= 'linear') which = ' and '//trim(config%shape)//' shapes'
      write (error_unit, '(a)') 'mpm1d: warning: dt_fraction = '//num(config%dt_fraction)//' is above the '// &
         'linear stability limit of '//trim(config%scheme)//' with '//plural(config%particles_per_element, &
         'particle')//' per element'//which//' (about '// &
         num(stability_limit(config%scheme, config%particles_per_element, config%shape), 3)// &
         ' of dx/c; see studies/stability and studies/shapes); a guard will stop the run if it grows'
   end subroutine warn_stability

   !> What a sweep says before it starts (flushed: a redirected log of a killed sweep shows it), and
   !> its warnings.
   subroutine sweep_header(sweep, quiet, resume)
      type(sweep_t), intent(in) :: sweep
      logical, intent(in) :: quiet, resume
      type(config_t) :: config
      integer :: i, above, missed
      character(len=:), allocatable :: first_warning
      if (quiet) then
         continue
      else if (sweep%settings%shards > 1) then
         write (output_unit, '(a)') 'mpm1d: sweep shard '//str(sweep%settings%shard)//' of '// &
            str(sweep%settings%shards)//': '//str(size(sweep%cases))//' of '//plural(sweep%total_cases, 'case')
      else
         write (output_unit, '(a)') 'mpm1d: sweep of '//plural(size(sweep%cases), 'case')
      end if
      if (resume .and. .not. quiet) write (output_unit, '(a)') 'resumed: '//str(cases_done(sweep%cases))//' of '// &
         plural(size(sweep%cases), 'case')//' ran before (kept); '//str(size(sweep%cases) - cases_done(sweep%cases))// &
         ' to run'
      above = 0
      missed = 0
      do i = 1, size(sweep%cases)
         config = case_config(sweep, sweep%cases(i))
         if (len(config_warnings(config)) > 0) missed = missed + 1
         if (missed == 1 .and. len(config_warnings(config)) > 0) first_warning = config_warnings(config)
         if (above_stability_limit(config)) above = above + 1
      end do
      if (missed > 0) write (error_unit, '(a)') 'mpm1d: warning: '//plural(missed, 'case')//' of '// &
         str(size(sweep%cases))//': '//first_warning//trim(merge(' (the first of them)', '                    ', &
                                                               missed > 1))
      if (above > 0) write (error_unit, '(a)') 'mpm1d: warning: '//plural(above, 'case')// &
         trim(merge(' asks', ' ask ', above == 1))//' for a time step '// &
         'above their scheme''s linear stability limit (see studies/stability); guards will stop them if they grow'
      ! the timing pass's cost, said before it is spent (most batch users want the error pass alone)
      if (sweep%settings%min_time > 0 .and. .not. quiet) write (output_unit, '(a)') 'timing pass after the '// &
         'error pass: each case repeated until '//num(sweep%settings%min_time)//' s of run time, at least '// &
         num(size(sweep%cases)*sweep%settings%min_time/sweep%settings%timing_threads, 3)//' s on '// &
         plural(sweep%settings%timing_threads, 'thread')//' (sweep.min_time=0 skips it)'
      flush (output_unit)
   end subroutine sweep_header

   !> What a sweep reports on standard output when it has written its file. A resumed sweep's pass times
   !> are summed over its attempts (the file's /sweep attributes hold the sums): `earlier` gives the error
   !> and timing pass times of the attempts before this one, and the report says so.
   subroutine report_sweep(sweep, output, earlier)
      type(sweep_t), intent(in) :: sweep
      character(len=*), intent(in) :: output
      real(dp), intent(in), optional :: earlier(2)
      integer :: done, stopped
      character(len=:), allocatable :: error_pass, timing_pass
      error_pass = 'error pass '//num(sweep%error_pass_time, 3)//' s on '//plural(sweep%threads_used, 'thread')
      timing_pass = 'timing pass '//num(sweep%timing_pass_time, 3)//' s on '// &
                    plural(sweep%settings%timing_threads, 'thread')
      if (present(earlier)) then
         error_pass = error_pass//' (summed over the attempts: this one '// &
                      num(sweep%error_pass_time - earlier(1), 3)//' s, the earlier ones '//num(earlier(1), 3)//' s)'
         timing_pass = timing_pass//' (summed over the attempts: this one '// &
                       num(sweep%timing_pass_time - earlier(2), 3)//' s, the earlier ones '//num(earlier(2), 3)//' s)'
      end if
      if (sweep%settings%min_time > 0) then
         write (output_unit, '(a)') error_pass//'; '//timing_pass//' (min_time '//num(sweep%settings%min_time)// &
            ' s per case)'
      else
         write (output_unit, '(a)') error_pass//'; no timing pass (min_time = 0)'
      end if
      done = cases_done(sweep%cases)
      stopped = count(sweep%cases%status /= status_ok .and. sweep%cases%status /= status_not_run)
      if (stopped > 0) then
         write (output_unit, '(a)') plural(done - stopped, 'case')//' completed, '//str(stopped)// &
            ' stopped by a guard (recorded in /cases/status; no max_error: see error_before_stop)'
      else
         write (output_unit, '(a)') plural(done, 'case')//' completed, none stopped by a guard'
      end if
      if (done < size(sweep%cases)) write (output_unit, '(a)') str(size(sweep%cases) - done)//' not run '// &
         '(status not_run, no values)'
      write (output_unit, '(a)') 'wrote '//absolute_path(output)
      flush (output_unit)
   end subroutine report_sweep

   !> A sweep stopped by a signal: what it finished is written; say so, how to go on (`command`: the
   !> command that resumes it, without --resume), and end with 128 + the signal's number (130 SIGINT,
   !> 143 SIGTERM, 129 SIGHUP), as the signal would have.
   subroutine interrupted(sweep, output, command)
      type(sweep_t), intent(in) :: sweep
      character(len=*), intent(in) :: output, command
      character(len=:), allocatable :: how, what
      how = command
      if (sweep%settings%shards > 1) how = how//' --shard '//str(sweep%settings%shard)//'/'//str(sweep%settings%shards)
      if (sweep%interrupted_timing) then
         what = ', in the timing pass ('//str(cases_timed(sweep%cases))//' of '// &
                str(count(sweep%cases%status == status_ok))//' completed cases timed; the others'' run_time is NaN) '// &
                'in '//absolute_path(output)//'; '//how//' --resume times them'
      else
         what = '; the others have status not_run (no values) in '//absolute_path(output)//'; '//how// &
                ' --resume runs them'
      end if
      write (error_unit, '(a)') 'mpm1d: interrupted after '//str(cases_done(sweep%cases))//' of '// &
         plural(size(sweep%cases), 'case')//what
      call ieee_set_flag(ieee_all, .false.)
      stop 128 + sweep%interrupted_by, quiet=.true.
   end subroutine interrupted

   !> `--dry-run` of a sweep: the number of cases and the absolute output path (and the shards' files
   !> when it is sharded), nothing run. Lines `cases: N`, `output: PATH` for scripts.
   subroutine report_dry_run(sweep)
      type(sweep_t), intent(in) :: sweep
      integer :: k
      associate (s => sweep%settings)
         if (s%shards > 1) then
            write (output_unit, '(a)') 'mpm1d: dry run (nothing runs): a sweep of '//plural(sweep%total_cases, 'case')// &
               ' in '//str(s%shards)//' shards (this command: shard '//str(s%shard)//')'
         else
            write (output_unit, '(a)') 'mpm1d: dry run (nothing runs): a sweep of '//plural(sweep%total_cases, 'case')
         end if
         write (output_unit, '(a)') 'cases: '//str(sweep%total_cases)
         if (s%shards > 1) write (output_unit, '(a)') 'shards: '//str(s%shards)
         write (output_unit, '(a)') 'output: '//absolute_path(trim(sweep%base%file))
         if (s%shards == 1) return
         do k = 1, s%shards
            write (output_unit, '(a)') 'shard '//str(k)//': '//plural(shard_cases(sweep%total_cases, k, s%shards), &
               'case')//', '//absolute_path(shard_file(trim(sweep%base%file), k, s%shards))
         end do
      end associate
   end subroutine report_dry_run
end module mpm_cli_report
