!> mpm1d command line: `mpm1d [input.nml | -] [group.name=value ...] [--quiet] [--shard I/N] [--threads N]
!> [--resume] [--dry-run]`, `mpm1d merge OUT IN...`,
!> `mpm1d --help`, `mpm1d --list-parameters`, `mpm1d --version`. An input file with a &sweep group runs a sweep.
!> Parses arguments, calls the library, prints messages and sets the exit code:
!> 0 success, 1 a guard stopped the run (its history is still written), 2 bad input or usage,
!> 3 output could not be written; a sweep interrupted by SIGINT, SIGTERM or SIGHUP (what it finished is
!> written) 130, 143, 129 (128 + the signal's number).
program mpm1d_main
   use, intrinsic :: iso_fortran_env, only: output_unit, error_unit
   use, intrinsic :: ieee_arithmetic, only: ieee_set_flag, ieee_all
   use mpm_kinds, only: dp
   use mpm_errors, only: error_t
   use mpm_strings, only: str, num, plural, readable_numbers
   use mpm_config, only: config_t, read_config_text, default_config, write_config_namelist, config_summary, stability_limit, &
                         check_output_path, config_warnings
   use mpm_simulation, only: run_result_t, run_simulation, guard_message
   use mpm_output, only: write_run_file
   use mpm_diagnostics, only: status_ok, status_not_run
   use mpm_version, only: code_version
   use mpm_cli_help, only: print_help, print_parameters
   use mpm_sweep, only: sweep_t, read_sweep_text, run_sweep, has_sweep_text, case_config, &
                        sweep_output_file, shard_file, shard_cases, cases_done, cases_timed, cases_to_time
   use mpm_files, only: same_file, absolute_path, catch_interrupts
   use mpm_registry, only: read_input_text
   use mpm_command_line, only: command_line_t, command_arguments, parse_command_line, check_environment, &
                               check_has_groups, override_length
   use mpm_sweep_output, only: write_sweep_file, merge_sweep_files, resume_sweep
   implicit none

   type(config_t) :: config
   type(run_result_t) :: result
   type(error_t), allocatable :: error
   type(command_line_t) :: command_line
   character(len=:), allocatable :: input, text, source
   character(len=override_length), allocatable :: overrides(:)
   integer :: shard, shards, threads
   !> Fewest elements per wavelength of the mode before a run is warned (two resolve a wave at best).
   integer, parameter :: min_elements_per_wavelength = 2
   logical :: quiet, is_sweep, resume, dry_run

   call parse_command_line(command_arguments(), command_line, error)
   if (allocated(error)) call fail(error%message, 2)
   select case (command_line%action)
   case ('help')
      call print_help(output_unit)
      stop
   case ('list-parameters')
      call print_parameters(output_unit)
      stop
   case ('version')
      write (output_unit, '(a)') code_version
      stop
   case ('merge')
      call merge_command()
      call finish()
   end select
   call check_environment(error)
   if (allocated(error)) call fail(error%message, 2)
   quiet = command_line%quiet
   shard = command_line%shard
   shards = command_line%shards
   threads = command_line%threads
   resume = command_line%resume
   dry_run = command_line%dry_run
   overrides = command_line%overrides
   if (command_line%has_input) input = command_line%input

   if (allocated(input)) then
      source = input
      if (input == '-') source = 'standard input'
      call read_input_text(input, text, error)
      if (allocated(error)) call fail('invalid input:'//new_line('a')//error%message, 2)
      call check_has_groups(text, source, error)
      if (allocated(error)) call fail('invalid input:'//new_line('a')//error%message, 2)
   else
      source = 'command line'
      text = ''
   end if
   is_sweep = has_sweep_text(text) .or. any(overrides(:)(1:6) == 'sweep.')
   if (is_sweep) then
      call sweep_command()
      call finish()
   end if
   if (shards > 0 .or. threads >= 0) call fail('--shard and --threads are for a sweep (an input with a &sweep '// &
                                                'group); see mpm1d --help', 2)
   if (resume) call fail('--resume is for a sweep (an input with a &sweep group): a single run has nothing to '// &
                         'resume; see mpm1d --help', 2)
   call read_config_text(text, source, config, error, overrides=overrides)
   if (allocated(error)) call fail('invalid input:'//new_line('a')//error%message, 2)
   call refuse_input_as_output(trim(config%file))
   if (dry_run) then
      write (output_unit, '(a)') 'mpm1d: dry run (nothing runs): a single run', 'cases: 1', &
         'output: '//absolute_path(trim(config%file))
      call finish()
   end if
   if (.not. allocated(input) .and. .not. quiet) then
      if (size(overrides) == 0) then
         write (output_unit, '(a)') 'mpm1d: no input file given; running the built-in verification case '// &
            '(see mpm1d --help for the namelist reference)'
      else
         write (output_unit, '(a)') 'mpm1d: no input file given; running the built-in verification case '// &
            'with the overrides given'
      end if
   end if

   ! (the implicit integrators are unconditionally stable: no limit to warn of)
   call warn_stability(config%scheme, config%particles_per_element, config%dt_fraction, &
                       merge(1, 0, trim(config%integrator) == 'explicit'), config%shape)
   if (len(config_warnings(config)) > 0) write (error_unit, '(a)') 'mpm1d: warning: '//config_warnings(config)
   if (unresolved(config)) write (error_unit, '(a)') 'mpm1d: warning: mode '//str(config%mode)//' has '// &
      num(elements_per_wavelength(config), 3)//' elements per wavelength on '//plural(config%elements, 'element')// &
      ' (wavelength 4 L/(2 mode - 1)); below '//str(min_elements_per_wavelength)//' the mesh cannot represent it '// &
      'and the error says little about the method'
   if (.not. quiet) then
      write (output_unit, '(a)') '# configuration used:'
      call write_config_namelist(output_unit, config)
      write (output_unit, '(a)') '# '//config_summary(config)
   end if

   call run_simulation(config, result, error, record_history=config%history)
   if (allocated(error)) call fail(error%message, 3)
   call write_run_file(config, result, error)
   if (allocated(error)) call fail(error%message, 3)

   if (.not. quiet) call report_run()
   ! u_cm is a mean of positions x_p - X_p: below a few hundred roundings of x it measures rounding
   if (result%ucm_amplitude < 100*spacing(config%length)) write (error_unit, '(a)') 'mpm1d: warning: the exact '// &
      'u_cm amplitude '//num(result%ucm_amplitude)//' m is below 100 times the rounding of positions near x = L ('// &
      num(spacing(config%length), 3)//' m): the error measures rounding, not the method; raise velocity_amplitude'
   ! the terminal gets the guard's message with readable numbers (the file keeps them in full)
   if (result%status /= status_ok) call fail(readable_numbers(guard_message(result%status, result%trip, config), 5)// &
                                             new_line('a')// &
                                             'the history up to that step is in '// &
                                             absolute_path(trim(config%file)), 1)
   call finish()

contains



   !> Normal end: floating-point flags a run raised on purpose (an energy sum computed again in scaled
   !> form, subnormal intermediates of a far-scaled bar) are no news to the user: no runtime note.
   subroutine finish()
      call ieee_set_flag(ieee_all, .false.)
      stop 0, quiet=.true.
   end subroutine finish

   !> What a single run reports on standard output. A run a guard stopped has no result: the error
   !> reached up to the stop is said as such (the file's max_error is NaN, error_before_stop holds it).
   subroutine report_run()
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

   !> Refuse an output file that is the input file (it would be overwritten).
   subroutine refuse_input_as_output(output)
      character(len=*), intent(in) :: output
      if (.not. allocated(input)) return
      if (input == '-') return
      if (same_file(input, output)) call fail("output: file = '"//output//"' is the input file '"//input// &
                                              "'; allowed: another file", 2)
   end subroutine refuse_input_as_output

   pure real(dp) function elements_per_wavelength(c)
      type(config_t), intent(in) :: c
      elements_per_wavelength = 4*real(c%elements, dp)/(2*real(c%mode, dp) - 1)
   end function elements_per_wavelength

   !> Does the mesh have fewer than min_elements_per_wavelength elements per wavelength of the mode?
   pure logical function unresolved(c)
      type(config_t), intent(in) :: c
      unresolved = elements_per_wavelength(c) < min_elements_per_wavelength
   end function unresolved



   !> `mpm1d input.nml [overrides] [--shard I/N] [--threads N] [--quiet] [--resume] [--dry-run]` for an input
   !> with a &sweep group.
   subroutine sweep_command()
      type(sweep_t) :: sweep
      character(len=:), allocatable :: output
      call read_sweep_text(text, source, sweep, error, shard, shards, threads, overrides)
      if (allocated(error)) call fail('invalid input:'//new_line('a')//error%message, 2)
      if (quiet) sweep%settings%progress = .false.
      output = sweep_output_file(sweep)
      call refuse_input_as_output(output)
      ! a shard's own file name, checked as the namelist's file is (a folder there is refused now)
      if (output /= trim(sweep%base%file)) call check_output_path(output, 'output: file of this shard', error)
      if (allocated(error)) call fail('invalid input:'//new_line('a')//error%message, 2)
      if (dry_run) then
         call report_dry_run(sweep)
         call finish()
      end if
      if (resume) then
         call resume_sweep(output, sweep, error)
         if (allocated(error)) call fail(error%message, 2)
         if (cases_done(sweep%cases) == size(sweep%cases) .and. (sweep%settings%min_time <= 0 .or. &
             .not. any(cases_to_time(sweep%cases)))) then
            if (.not. quiet) write (output_unit, '(a)') 'mpm1d: nothing to resume: every case of '// &
               absolute_path(output)//' ran'//trim(merge(' and was timed', '              ', &
               sweep%settings%min_time > 0))//'; the file is left as it is'
            call finish()
         end if
      end if
      ! from the header on, a signal stops the sweep and keeps what it finished (a script that waits for
      ! the header before it signals finds the sweep catching)
      call catch_interrupts()
      call sweep_header(sweep)
      call run_sweep(sweep, catch_signals=.true.)
      if (resume) then
         call write_sweep_file(output, sweep, error, previous=output)
      else
         call write_sweep_file(output, sweep, error)
      end if
      if (allocated(error)) call fail(error%message, 3)
      if (.not. quiet) call report_sweep(sweep, output)
      if (sweep%interrupted_by /= 0) call interrupted(sweep, output)
   end subroutine sweep_command

   !> What a sweep says before it starts (flushed: a redirected log of a killed sweep shows it), and
   !> its warnings.
   subroutine sweep_header(sweep)
      type(sweep_t), intent(in) :: sweep
      integer :: i, above, coarse, missed
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
      coarse = 0
      missed = 0
      do i = 1, size(sweep%cases)
         config = case_config(sweep, sweep%cases(i))
         if (len(config_warnings(config)) > 0) missed = missed + 1
         if (missed == 1 .and. len(config_warnings(config)) > 0) first_warning = config_warnings(config)
         if (config%dt_fraction > stability_limit(config%scheme, config%particles_per_element, config%shape) .and. &
             trim(config%integrator) == 'explicit') above = above + 1
         if (unresolved(config)) coarse = coarse + 1
      end do
      if (missed > 0) write (error_unit, '(a)') 'mpm1d: warning: '//plural(missed, 'case')//' of '// &
         str(size(sweep%cases))//': '//first_warning//trim(merge(' (the first of them)', '                    ', &
                                                               missed > 1))
      if (coarse > 0) write (error_unit, '(a)') 'mpm1d: warning: '//plural(coarse, 'case')//' ha'// &
         trim(merge('s ', 've', coarse == 1))//' fewer than '//str(min_elements_per_wavelength)//' elements per '// &
         'wavelength of the mode (wavelength 4 L/(2 mode - 1)): the mesh cannot represent it'
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

   !> What a sweep reports on standard output when it has written its file.
   subroutine report_sweep(sweep, output)
      type(sweep_t), intent(in) :: sweep
      character(len=*), intent(in) :: output
      integer :: done, stopped
      if (sweep%settings%min_time > 0) then
         write (output_unit, '(a)') 'error pass '//num(sweep%error_pass_time, 3)//' s on '// &
            plural(sweep%threads_used, 'thread')//'; timing pass '//num(sweep%timing_pass_time, 3)//' s on '// &
            plural(sweep%settings%timing_threads, 'thread')//' (min_time '//num(sweep%settings%min_time)//' s per case)'
      else
         write (output_unit, '(a)') 'error pass '//num(sweep%error_pass_time, 3)//' s on '// &
            plural(sweep%threads_used, 'thread')//'; no timing pass (min_time = 0)'
      end if
      done = cases_done(sweep%cases)
      stopped = count(sweep%cases%status /= status_ok .and. sweep%cases%status /= status_not_run)
      write (output_unit, '(a)') plural(done - stopped, 'case')//' completed, '//str(stopped)// &
         ' stopped by a guard (recorded in /cases/status; no max_error: see error_before_stop)'
      if (done < size(sweep%cases)) write (output_unit, '(a)') str(size(sweep%cases) - done)//' not run '// &
         '(status not_run, no values)'
      write (output_unit, '(a)') 'wrote '//absolute_path(output)
      flush (output_unit)
   end subroutine report_sweep

   !> A sweep stopped by a signal: what it finished is written; say so, how to go on, and end with
   !> 128 + the signal's number (130 SIGINT, 143 SIGTERM, 129 SIGHUP), as the signal would have.
   subroutine interrupted(sweep, output)
      type(sweep_t), intent(in) :: sweep
      character(len=*), intent(in) :: output
      character(len=:), allocatable :: how, what
      how = 'mpm1d'
      if (allocated(input)) how = how//' '//input
      if (size(overrides) > 0) how = how//' (the same overrides)'
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

   !> Warn (standard error) when the time step is above the stability limit of the scheme and shape.
   subroutine warn_stability(scheme, particles_per_element, dt_fraction, cases, shape)
      character(len=*), intent(in) :: scheme, shape
      integer, intent(in) :: particles_per_element, cases
      real(dp), intent(in) :: dt_fraction
      real(dp) :: limit
      character(len=:), allocatable :: which
      which = ''
      if (trim(shape) /= 'linear') which = ' and '//trim(shape)//' shapes'
      limit = stability_limit(scheme, particles_per_element, shape)
      if (dt_fraction > limit .and. cases > 0) write (error_unit, '(a)') 'mpm1d: warning: dt_fraction = '// &
         num(dt_fraction)//' is above the linear stability limit of '//trim(scheme)//' with '// &
         plural(particles_per_element, 'particle')//' per element'//which//' (about '//num(limit, 3)// &
         ' of dx/c; see studies/stability and studies/shapes); a guard will stop the run if it grows'
   end subroutine warn_stability





   !> `mpm1d merge OUT.h5 SHARD.h5 ...`
   subroutine merge_command()
      character(len=:), allocatable :: output
      integer :: i
      logical :: output_failed
      associate (files => command_line%merge_files)
         output = trim(files(1))
         do i = 2, size(files)
            if (same_file(output, trim(files(i)))) call fail("merge: the output '"//output//"' is one of the "// &
                                                             "shard files; allowed: a new file", 2)
         end do
         call merge_sweep_files(output, files(2:), error, output_failed)
         if (allocated(error)) call fail(error%message, merge(3, 2, output_failed))
         write (output_unit, '(a)') 'wrote '//absolute_path(output)//' from '//str(size(files) - 1)//' shard files'
      end associate
   end subroutine merge_command

   subroutine fail(message, code)
      character(len=*), intent(in) :: message
      integer, intent(in) :: code
      write (error_unit, '(a)') 'mpm1d: '//message
      stop code, quiet=.true.
   end subroutine fail
end program mpm1d_main
