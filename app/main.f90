!> mpm1d command line: `mpm1d [input.nml | -] [group.name=value ...] [--quiet] [--shard I/N] [--threads N]
!> [--resume] [--restart] [--dry-run]`, `mpm1d merge OUT IN...`,
!> `mpm1d --help`, `mpm1d --list-parameters`, `mpm1d --version`. An input file with a &sweep group runs a sweep.
!> Parses arguments, calls the library, prints messages and sets the exit code:
!> 0 success, 1 a guard stopped the run (its history is still written), 2 bad input or usage,
!> 3 output could not be written; a sweep interrupted by SIGINT, SIGTERM or SIGHUP (what it finished is
!> written), or a single run (after the step it is in: its state kept in the checkpoint where it keeps
!> them, else nothing written), 130, 143, 129 (128 + the signal's number).
program mpm1d_main
   use, intrinsic :: iso_fortran_env, only: output_unit
   use mpm_kinds, only: dp
   use mpm_errors, only: error_t
   use mpm_strings, only: str
   use mpm_config, only: config_t, read_config_text, check_output_path
   use mpm_simulation, only: run_result_t, run_simulation
   use mpm_diagnostics, only: status_not_run
   use mpm_state, only: state_t
   use mpm_checkpoint, only: checkpoint_file_t, checkpoint_for, read_checkpoint
   use mpm_output, only: write_run_file
   use mpm_version, only: code_version
   use mpm_cli_help, only: print_help, print_parameters
   use mpm_sweep, only: sweep_t, read_sweep_text, run_sweep, has_sweep_text, sweep_output_file, cases_done, &
                        cases_to_time
   use mpm_files, only: same_file, absolute_path, catch_interrupts, file_size_errors, interrupt_signal, remove_file, &
                        release_interrupts
   use mpm_registry, only: read_input_text
   use mpm_command_line, only: command_line_t, command_arguments, parse_command_line, check_environment, &
                               check_has_groups
   use mpm_sweep_output, only: write_sweep_file, merge_sweep_files, resume_sweep, open_sweep_journal, close_sweep_journal
   use mpm_cli_report, only: fail, finish, warn_run, report_config, report_run, warn_rounding, stop_for_guard, &
                             sweep_header, report_sweep, interrupted, report_dry_run, report_journal, warn
   implicit none

   type(error_t), allocatable :: error
   type(command_line_t) :: cl
   character(len=:), allocatable :: text, source

   call file_size_errors()
   call parse_command_line(command_arguments(), cl, error)
   if (allocated(error)) call fail(error%message, 2)
   select case (cl%action)
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
   call read_input()
   if (has_sweep_text(text) .or. any(cl%overrides(:)(1:6) == 'sweep.')) then
      call sweep_command()
   else
      call single_run()
   end if
   call finish()

contains

   !> The input's text and what to call it in messages (the file, standard input, or the command line).
   subroutine read_input()
      if (.not. cl%has_input) then
         source = 'command line'
         text = ''
         return
      end if
      source = cl%input
      if (cl%input == '-') source = 'standard input'
      call read_input_text(cl%input, text, error)
      if (allocated(error)) call fail('invalid input:'//new_line('a')//error%message, 2)
      call check_has_groups(text, source, error)
      if (allocated(error)) call fail('invalid input:'//new_line('a')//error%message, 2)
   end subroutine read_input

   !> One run: read and check the configuration, warn, run, write the file, report.
   subroutine single_run()
      type(config_t) :: config
      type(run_result_t) :: result
      type(checkpoint_file_t) :: checkpoints
      type(state_t) :: state
      integer :: step
      if (cl%shards > 0 .or. cl%threads >= 0) call fail('--shard and --threads are for a sweep (an input with a '// &
                                                        '&sweep group); see mpm1d --help', 2)
      if (cl%resume) call fail('--resume is for a sweep (an input with a &sweep group): a single run has nothing '// &
                               'to resume (--restart continues a single run from its checkpoint); see mpm1d --help', 2)
      call read_config_text(text, source, config, error, overrides=cl%overrides)
      if (allocated(error)) call fail('invalid input:'//new_line('a')//error%message, 2)
      call refuse_input_as_output(trim(config%file))
      if (cl%dry_run) then
         write (output_unit, '(a)') 'mpm1d: dry run (nothing runs): a single run', 'cases: 1', &
            'output: '//absolute_path(trim(config%file)), 'steps: '//str(config%steps)
         call finish()
      end if
      if (.not. cl%has_input .and. .not. cl%quiet) then
         if (size(cl%overrides) == 0) then
            write (output_unit, '(a)') 'mpm1d: no input file given; running the built-in verification case '// &
               '(see mpm1d --help for the namelist reference)'
         else
            write (output_unit, '(a)') 'mpm1d: no input file given; running the built-in verification case '// &
               'with the overrides given'
         end if
      end if
      ! a signal stops the run after the step it is in (the run says so; one that keeps checkpoints keeps
      ! one there), caught before the header that tells a watcher the run has begun
      call catch_interrupts()
      call warn_run(config)
      if (.not. cl%quiet) call report_config(config)
      checkpoints = checkpoint_for(config)
      if (cl%restart) then
         call read_checkpoint(config, state, step, error)
         if (allocated(error)) call fail(error%message, 2)
         if (.not. cl%quiet) write (output_unit, '(a)') 'mpm1d: restarted from step '//str(step)//' of '// &
            str(config%steps)//" (the checkpoint '"//checkpoints%path//"')"
      end if
      if (cl%restart) then
         call run_simulation(config, result, error, record_history=config%history, checkpoints=checkpoints, &
                             restart=state)
         if (allocated(error)) call fail("restart: the checkpoint '"//checkpoints%path//"' is damaged: "// &
                                         error%message//"; allowed: an undamaged checkpoint, or run without "// &
                                         "--restart to start afresh", 2)
      else
         call run_simulation(config, result, error, record_history=config%history, checkpoints=checkpoints)
         if (allocated(error)) call fail(error%message, 3)
      end if
      if (allocated(checkpoints%failure)) call warn(checkpoints%failure//' (the run went on without it)')
      if (result%status == status_not_run) call stopped_run(checkpoints, result%steps_done, config%steps)
      ! (from here a signal ends the process at once, removing the file being written: the checkpoint stays)
      call release_interrupts()
      call write_run_file(config, result, error)
      if (allocated(error)) call fail(error%message, 3)
      ! the run's file is complete: its checkpoint (this run's, or an earlier run's into this file) is done
      call remove_file(checkpoints%path)
      if (.not. cl%quiet) call report_run(config, result)
      call warn_rounding(config, result)
      call stop_for_guard(config, result)
   end subroutine single_run

   !> A run stopped by a signal after step `step` of `steps`: where its state is (in its checkpoint where
   !> it keeps them) and how to go on; the exit code 128 + the signal's number.
   subroutine stopped_run(checkpoints, step, steps)
      type(checkpoint_file_t), intent(in) :: checkpoints
      integer, intent(in) :: step, steps
      integer :: signal
      signal = interrupt_signal()
      if (checkpoints%every <= 0) then
         call fail(signal_name(signal)//' stopped the run after step '//str(step)//' of '//str(steps)// &
                   '; nothing was written (&output checkpoint_steps = N keeps a long run''s state every N '// &
                   'steps, and --restart continues it from there)', 128 + signal)
      else if (checkpoints%step == step) then
         call fail(signal_name(signal)//' stopped the run after step '//str(step)//' of '//str(steps)// &
                   "; the checkpoint '"//checkpoints%path//"' keeps it: "//restart_command()// &
                   ' continues from there', 128 + signal)
      else
         call fail(signal_name(signal)//' stopped the run after step '//str(step)//' of '//str(steps)// &
                   "; its checkpoint could not be written ("//checkpoints%failure//')', 128 + signal)
      end if
   end subroutine stopped_run

   !> The command that restarts this run.
   function restart_command() result(how)
      character(len=:), allocatable :: how
      how = 'mpm1d'
      if (cl%has_input) how = how//' '//cl%input
      if (size(cl%overrides) > 0) how = how//' (with its overrides)'
      how = how//' --restart'
   end function restart_command

   function signal_name(signal) result(name)
      integer, intent(in) :: signal
      character(len=:), allocatable :: name
      select case (signal)
      case (1)
         name = 'SIGHUP'
      case (2)
         name = 'SIGINT'
      case (15)
         name = 'SIGTERM'
      case default
         name = 'signal '//str(signal)
      end select
   end function signal_name

   !> `mpm1d input.nml [overrides] [--shard I/N] [--threads N] [--quiet] [--resume] [--dry-run]` for an input
   !> with a &sweep group.
   subroutine sweep_command()
      type(sweep_t) :: sweep
      character(len=:), allocatable :: output, warning
      real(dp) :: earlier(2)  !< a resumed sweep's error and timing pass times before this attempt
      call read_sweep_text(text, source, sweep, error, cl%shard, cl%shards, cl%threads, cl%overrides)
      if (allocated(error)) call fail('invalid input:'//new_line('a')//error%message, 2)
      if (cl%quiet) sweep%settings%progress = .false.
      output = sweep_output_file(sweep)
      call refuse_input_as_output(output)
      ! a shard's own file name, checked as the namelist's file is (a folder there is refused now)
      if (output /= trim(sweep%base%file)) call check_output_path(output, 'output: file of this shard', error)
      if (allocated(error)) call fail('invalid input:'//new_line('a')//error%message, 2)
      if (cl%dry_run) then
         call report_dry_run(sweep)
         call finish()
      end if
      if (cl%resume) then
         call resume_sweep(output, sweep, error)
         if (allocated(error)) call fail(error%message, 2)
         earlier = [sweep%error_pass_time, sweep%timing_pass_time]
      end if
      ! each case is appended to the journal as it finishes (a kill loses only the cases running)
      call open_sweep_journal(output, sweep, cl%resume, warning, error)
      if (allocated(error)) call fail(error%message, 2)
      if (len(warning) > 0) call warn(warning)
      if (cl%resume .and. sweep%journal_records == 0 .and. cases_done(sweep%cases) == size(sweep%cases) .and. &
          (sweep%settings%min_time <= 0 .or. .not. any(cases_to_time(sweep%cases)))) then
         call close_sweep_journal(sweep, written=.true.)
         if (.not. cl%quiet) write (output_unit, '(a)') 'mpm1d: nothing to resume: every case of '// &
            absolute_path(output)//' ran'//trim(merge(' and was timed', '              ', &
            sweep%settings%min_time > 0))//'; the file is left as it is'
         call finish()
      end if
      ! from the header on, a signal stops the sweep and keeps what it finished (a script that waits for
      ! the header before it signals finds the sweep catching)
      call catch_interrupts()
      call sweep_header(sweep, cl%quiet, cl%resume)
      if (cl%resume) call report_journal(sweep, cl%quiet)
      call run_sweep(sweep, catch_signals=.true.)
      call write_sweep_file(output, sweep, error)
      call close_sweep_journal(sweep, written=.not. allocated(error))
      if (allocated(error)) call fail(error%message//journal_kept(sweep), 3)
      if (allocated(sweep%journal%failure)) call warn("the journal '"//sweep%journal%path//"' took no more "// &
         "records after its "//str(sweep%journal%appended)//" first: "//sweep%journal%failure//"; a kill before "// &
         "the output was written would have lost the cases after them")
      if (.not. cl%quiet) then
         if (cl%resume) then
            call report_sweep(sweep, output, earlier)
         else
            call report_sweep(sweep, output)
         end if
      end if
      if (sweep%interrupted_by /= 0) call interrupted(sweep, output, resume_command())
   end subroutine sweep_command

   !> What the journal kept when a sweep's output could not be written, and how to go on ('' when it
   !> kept nothing).
   function journal_kept(sweep) result(text)
      type(sweep_t), intent(in) :: sweep
      character(len=:), allocatable :: text, how
      text = ''
      if (sweep%journal%appended <= 1 .and. sweep%journal_records == 0) return
      how = resume_command()
      if (sweep%settings%shards > 1) how = how//' --shard '//str(sweep%settings%shard)//'/'//str(sweep%settings%shards)
      if (allocated(sweep%journal%failure)) then
         text = new_line('a')//"the journal '"//sweep%journal%path//"' keeps the cases finished before it too "// &
                "failed ("//sweep%journal%failure//"): free space (or mend the cause), then "//how//" --resume "// &
                "runs only the others and writes the file"
      else
         text = new_line('a')//"the finished cases are kept in the journal '"//sweep%journal%path//"': free "// &
                "space (or mend the cause), then "//how//" --resume writes the file without running them again"
      end if
   end function journal_kept

   !> The command that resumes this sweep (--resume and a shard's --shard are added by the message).
   function resume_command() result(how)
      character(len=:), allocatable :: how
      how = 'mpm1d'
      if (cl%has_input) how = how//' '//cl%input
      if (size(cl%overrides) > 0) how = how//' (the same overrides)'
   end function resume_command

   !> Refuse an output file that is the input file (it would be overwritten).
   subroutine refuse_input_as_output(output)
      character(len=*), intent(in) :: output
      if (.not. cl%has_input) return
      if (cl%input == '-') return
      if (same_file(cl%input, output)) call fail("output: file = '"//output//"' is the input file '"//cl%input// &
                                                 "'; allowed: another file", 2)
   end subroutine refuse_input_as_output

   !> `mpm1d merge OUT.h5 SHARD.h5 ...`
   subroutine merge_command()
      character(len=:), allocatable :: output
      integer :: i
      logical :: output_failed
      associate (files => cl%merge_files)
         output = trim(files(1))
         do i = 2, size(files)
            if (same_file(output, trim(files(i)))) call fail("merge: the output '"//output//"' is one of the "// &
                                                             "shard files; allowed: a new file", 2)
         end do
         call merge_sweep_files(output, files(2:), error, output_failed)
         if (allocated(error)) call fail(error%message, merge(3, 2, output_failed))
         write (output_unit, '(a)') 'wrote '//absolute_path(output)//' from '//str(size(files) - 1)// &
            ' shard files'
      end associate
   end subroutine merge_command
end program mpm1d_main
