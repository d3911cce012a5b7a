!> mpm1d command line: `mpm1d [input.nml | -] [group.name=value ...] [--quiet] [--shard I/N] [--threads N]`,
!> `mpm1d merge OUT IN...`,
!> `mpm1d --help`, `mpm1d --list-parameters`, `mpm1d --version`. An input file with a &sweep group runs a sweep.
!> Parses arguments, calls the library, prints messages and sets the exit code:
!> 0 success, 1 a guard stopped the run (its history is still written), 2 bad input or usage,
!> 3 output could not be written.
program mpm1d_main
   use, intrinsic :: iso_fortran_env, only: output_unit, error_unit
   use, intrinsic :: ieee_arithmetic, only: ieee_set_flag, ieee_all
   use mpm_kinds, only: dp
   use mpm_errors, only: error_t
   use mpm_strings, only: str, num, plural, readable_numbers
   use mpm_config, only: config_t, read_config_text, default_config, write_config_namelist, config_summary, stability_limit, &
                         check_output_path
   use mpm_simulation, only: run_result_t, run_simulation, guard_message
   use mpm_output, only: write_run_file
   use mpm_diagnostics, only: status_ok
   use mpm_version, only: code_version
   use mpm_cli_help, only: print_help, print_parameters
   use mpm_sweep, only: sweep_t, read_sweep_text, run_sweep, has_sweep_text, case_config, max_threads
   use mpm_files, only: same_file
   use mpm_registry, only: read_input_text, parse_namelist, nml_item_t
   use mpm_sweep_output, only: write_sweep_file, merge_sweep_files
   implicit none

   type(config_t) :: config
   type(run_result_t) :: result
   type(error_t), allocatable :: error
   character(len=:), allocatable :: input, text, source, option
   character(len=1024), allocatable :: overrides(:)
   integer :: nargs, i, shard, shards, threads
   !> Fewest elements per wavelength of the mode before a run is warned (two resolve a wave at best).
   integer, parameter :: min_elements_per_wavelength = 2
   logical :: quiet, is_sweep

   nargs = command_argument_count()
   if (nargs >= 1) then
      select case (argument(1))
      case ('-h', '--help', '--list-parameters', '-V', '--version')
         if (nargs > 1) call fail("'"//argument(1)//"' takes no other arguments (given: '"//argument(2)// &
                                  "'); see mpm1d --help", 2)
      end select
      select case (argument(1))
      case ('-h', '--help')
         call print_help(output_unit)
         stop
      case ('--list-parameters')
         call print_parameters(output_unit)
         stop
      case ('-V', '--version')
         write (output_unit, '(a)') code_version
         stop
      case ('merge')
         call merge_command()
         call finish()
      end select
   end if

   call check_environment()
   ! the arguments: an input file (or '-'), overrides group.name=value, options
   allocate (overrides(0))
   quiet = .false.
   shard = 0
   shards = 0
   threads = -1
   i = 1
   do while (i <= nargs)
      option = argument(i)
      select case (option)
      case ('-q', '--quiet')
         quiet = .true.
      case ('--shard=':'--shard=~', '--threads=':'--threads=~')
         ! the --option=value form
         if (option(1:8) == '--shard=') then
            call parse_shard(option(9:), shard, shards)
         else
            threads = to_int(option(11:), '--threads')
            if (threads < 0 .or. threads > max_threads) call fail('--threads '//option(11:)// &
               ' is out of range; allowed: 0 (all cores) to '//str(max_threads), 2)
         end if
      case ('--shard', '--threads')
         if (i == nargs) call fail("option '"//option//"' needs a value; see mpm1d --help", 2)
         i = i + 1
         if (option == '--shard') then
            call parse_shard(argument(i), shard, shards)
         else
            threads = to_int(argument(i), '--threads')
            if (threads < 0 .or. threads > max_threads) call fail('--threads '//argument(i)// &
               ' is out of range; allowed: 0 (all cores) to '//str(max_threads), 2)
         end if
      case ('-')
         if (allocated(input)) call fail("too many input files: '"//input//"' and '-'; see mpm1d --help", 2)
         input = option
      case default
         if (len(option) == 0) call fail('argument '//str(i)//' is an empty argument; allowed: an input file, '// &
                                         'an override group.name=value or an option (see mpm1d --help)', 2)
         if (option(1:min(1, len(option))) == '-') call fail("unknown option '"//option//"'; see mpm1d --help", 2)
         if (is_override(option) .and. (allocated(input) .or. .not. exists(option))) then
            if (len(option) > len(overrides)) call fail("override '"//option(1:60)//"...' is too long; allowed: "// &
                                                       str(len(overrides))//" characters", 2)
            overrides = [character(len=len(overrides)) :: overrides, option]
         else if (.not. allocated(input)) then
            input = option
         else
            call fail("too many arguments: '"//option//"' after the input file '"//input// &
                      "'; usage: mpm1d [input.nml | -] [group.name=value ...] (see mpm1d --help)", 2)
         end if
      end select
      i = i + 1
   end do

   if (allocated(input)) then
      source = input
      if (input == '-') source = 'standard input'
      call read_input_text(input, text, error)
      if (allocated(error)) call fail('invalid input:'//new_line('a')//error%message, 2)
      call refuse_without_groups()
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
   call read_config_text(text, source, config, error, overrides=overrides)
   if (allocated(error)) call fail('invalid input:'//new_line('a')//error%message, 2)
   call refuse_input_as_output(trim(config%file))
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
                                             trim(config%file), 1)
   call finish()

contains

   !> OMP_NUM_THREADS, which a sweep's threads = 0 follows: whole numbers 1 to max_threads (a list
   !> "4,2" for nested levels); libgomp only warns about other text and crashes on 100000 threads.
   subroutine check_environment()
      character(len=:), allocatable :: value, item
      integer :: length, comma, n, stat
      call get_environment_variable('OMP_NUM_THREADS', length=length)
      if (length == 0) return
      allocate (character(len=length) :: value)
      call get_environment_variable('OMP_NUM_THREADS', value)
      value = trim(adjustl(value))
      if (len(value) == 0) return
      do
         comma = index(value, ',')
         item = trim(adjustl(value(1:merge(comma - 1, len(value), comma > 0))))
         n = -1
         stat = 1
         if (len(item) > 0 .and. len(item) <= 9 .and. verify(item, '0123456789') == 0) read (item, *, iostat=stat) n
         if (stat /= 0 .or. n < 1 .or. n > max_threads) call fail("environment: OMP_NUM_THREADS = '"//value// &
            "' is not a thread count; allowed: whole numbers 1 to "//str(max_threads)//" (comma-separated for "// &
            "nested levels), or leave it unset", 2)
         if (comma == 0) exit
         value = value(comma + 1:)
      end do
   end subroutine check_environment

   !> An input with no namelist group at all (empty, blanks or comments only, and every text the reader
   !> does not refuse line by line) is refused: the built-in case runs only without an input file.
   subroutine refuse_without_groups()
      type(nml_item_t), allocatable :: items(:)
      character(len=32), allocatable :: groups(:)
      integer, allocatable :: lines(:)
      type(error_t), allocatable :: problem
      call parse_namelist(text, source, items, groups, lines, problem)
      if (allocated(problem)) return ! reported with the file's other problems by the reader
      if (size(groups) == 0) call fail('invalid input:'//new_line('a')//source//': no namelist group (the input '// &
         'is empty or holds only blanks and comments); allowed: &group name=value, ... / groups (see mpm1d '// &
         '--help); run mpm1d without an input file for the built-in verification case', 2)
   end subroutine refuse_without_groups

   !> Normal end: floating-point flags a run raised on purpose (an energy sum computed again in scaled
   !> form, subnormal intermediates of a far-scaled bar) are no news to the user: no runtime note.
   subroutine finish()
      call ieee_set_flag(ieee_all, .false.)
      stop 0, quiet=.true.
   end subroutine finish

   !> What a single run reports on standard output.
   subroutine report_run()
      real(dp) :: rate
      rate = real(result%particles, dp)*result%steps_done/max(result%run_time, 1.0e-9_dp)
      write (output_unit, '(a)') 'max '//result%error_name//' = '//num(result%max_error)//' '//result%error_unit// &
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
   write (output_unit, '(a)') 'wrote '//trim(config%file)
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

   !> Is `text` an override `group.name=value`?
   logical function is_override(text)
      character(len=*), intent(in) :: text
      integer :: eq, dot
      eq = index(text, '=')
      is_override = .false.
      if (eq < 4) return
      dot = index(text(1:eq - 1), '.')
      if (dot < 2 .or. dot > eq - 2) return
      is_override = verify(text(1:eq - 1), 'abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789_.') == 0
   end function is_override

   logical function exists(path)
      character(len=*), intent(in) :: path
      inquire (file=path, exist=exists)
   end function exists

   !> `mpm1d input.nml [overrides] [--shard I/N] [--threads N] [--quiet]` for an input with a &sweep group.
   subroutine sweep_command()
      type(sweep_t) :: sweep
      integer :: i, failed, above, coarse
      character(len=:), allocatable :: output
      call read_sweep_text(text, source, sweep, error, shard, shards, threads, overrides)
      if (allocated(error)) call fail('invalid input:'//new_line('a')//error%message, 2)
      if (quiet) sweep%settings%progress = .false.
      output = trim(sweep%base%file)
      if (sweep%settings%shards > 1) output = shard_file(output, sweep%settings%shard, sweep%settings%shards)
      call refuse_input_as_output(output)
      ! a shard's own file name, checked as the namelist's file is (a folder there is refused now)
      if (output /= trim(sweep%base%file)) call check_output_path(output, 'output: file of this shard', error)
      if (allocated(error)) call fail('invalid input:'//new_line('a')//error%message, 2)
      if (quiet) then
         continue
      else if (sweep%settings%shards > 1) then
         write (output_unit, '(a)') 'mpm1d: sweep shard '//str(sweep%settings%shard)//' of '// &
            str(sweep%settings%shards)//': '//str(size(sweep%cases))//' of '//plural(sweep%total_cases, 'case')
      else
         write (output_unit, '(a)') 'mpm1d: sweep of '//plural(size(sweep%cases), 'case')
      end if
      above = 0
      coarse = 0
      do i = 1, size(sweep%cases)
         config = case_config(sweep, sweep%cases(i))
         if (config%dt_fraction > stability_limit(config%scheme, config%particles_per_element, config%shape) .and. &
             trim(config%integrator) == 'explicit') above = above + 1
         if (unresolved(config)) coarse = coarse + 1
      end do
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
      call run_sweep(sweep)
      call write_sweep_file(output, sweep, error)
      if (allocated(error)) call fail(error%message, 3)
      failed = count(sweep%cases%status /= status_ok)
      if (quiet) return
      if (sweep%settings%min_time > 0) then
         write (output_unit, '(a)') 'error pass '//num(sweep%error_pass_time, 3)//' s on '// &
            plural(sweep%threads_used, 'thread')//'; timing pass '//num(sweep%timing_pass_time, 3)//' s on '// &
            plural(sweep%settings%timing_threads, 'thread')//' (min_time '//num(sweep%settings%min_time)//' s per case)'
      else
         write (output_unit, '(a)') 'error pass '//num(sweep%error_pass_time, 3)//' s on '// &
            plural(sweep%threads_used, 'thread')//'; no timing pass (min_time = 0)'
      end if
      write (output_unit, '(a)') plural(size(sweep%cases) - failed, 'case')//' completed, '//str(failed)// &
         ' stopped by a guard (recorded in /cases/status)'
      write (output_unit, '(a)') 'wrote '//output
   end subroutine sweep_command

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
      character(len=1024), allocatable :: inputs(:)
      integer :: i
      logical :: output_failed
      if (nargs < 3) call fail('usage: mpm1d merge OUT.h5 SHARD1.h5 [SHARD2.h5 ...]', 2)
      do i = 2, nargs
         if (len(argument(i)) == 0) call fail('merge: argument '//str(i)//' is an empty argument; usage: '// &
                                             'mpm1d merge OUT.h5 SHARD1.h5 [SHARD2.h5 ...]', 2)
      end do
      allocate (inputs(nargs - 2))
      do i = 3, nargs
         inputs(i - 2) = argument(i)
      end do
      do i = 1, size(inputs)
         if (same_file(argument(2), inputs(i))) call fail("merge: the output '"//argument(2)//"' is one of the "// &
                                                          "shard files; allowed: a new file", 2)
      end do
      call merge_sweep_files(argument(2), inputs, error, output_failed)
      if (allocated(error)) call fail(error%message, merge(3, 2, output_failed))
      write (output_unit, '(a)') 'wrote '//argument(2)//' from '//str(size(inputs))//' shard files'
   end subroutine merge_command

   !> "I/N" -> shard I of N.
   subroutine parse_shard(text, shard, shards)
      character(len=*), intent(in) :: text
      integer, intent(out) :: shard, shards
      integer :: slash
      slash = index(text, '/')
      if (slash < 2) call fail("--shard "//text//" is malformed; allowed: I/N with 1 <= I <= N", 2)
      shard = to_int(text(1:slash - 1), '--shard')
      shards = to_int(text(slash + 1:), '--shard')
      if (shards < 1 .or. shard < 1 .or. shard > shards) &
         call fail("--shard "//text//" is out of range; allowed: I/N with 1 <= I <= N", 2)
   end subroutine parse_shard

   integer function to_int(text, name)
      character(len=*), intent(in) :: text, name
      integer :: stat
      read (text, *, iostat=stat) to_int
      if (stat /= 0 .or. verify(trim(text), '0123456789') /= 0) call fail(name//" '"//text// &
         "' is not a whole number", 2)
   end function to_int

   !> out.h5 -> out_shard002of004.h5
   function shard_file(path, shard, shards) result(name)
      character(len=*), intent(in) :: path
      integer, intent(in) :: shard, shards
      character(len=:), allocatable :: name
      character(len=48) :: suffix, form
      integer :: dot, width
      ! at least 3 digits (the names of up to 999 shards as before), as many as the shard count has
      width = max(3, len(str(shards)))
      write (form, '("(""_shard"",i",i0,".",i0,",""of"",i",i0,".",i0,")")') width, width, width, width
      write (suffix, form) shard, shards
      dot = index(path, '.h5', back=.true.)
      if (dot == len(path) - 2 .and. dot > 0) then
         name = path(1:dot - 1)//trim(suffix)//'.h5'
      else
         name = path//trim(suffix)
      end if
   end function shard_file

   function argument(i) result(text)
      integer, intent(in) :: i
      character(len=:), allocatable :: text
      integer :: length
      call get_command_argument(i, length=length)
      allocate (character(len=length) :: text)
      call get_command_argument(i, text)
   end function argument

   subroutine fail(message, code)
      character(len=*), intent(in) :: message
      integer, intent(in) :: code
      write (error_unit, '(a)') 'mpm1d: '//message
      stop code, quiet=.true.
   end subroutine fail
end program mpm1d_main
