!> mpm1d command line: `mpm1d [input.nml] [--shard I/N] [--threads N]`, `mpm1d merge OUT IN...`,
!> `mpm1d --help`, `mpm1d --list-parameters`, `mpm1d --version`. An input file with a &sweep group runs a sweep.
!> Parses arguments, calls the library, prints messages and sets the exit code:
!> 0 success, 1 a guard stopped the run (its history is still written), 2 bad input or usage,
!> 3 output could not be written.
program mpm1d_main
   use, intrinsic :: iso_fortran_env, only: output_unit, error_unit
   use mpm_kinds, only: dp
   use mpm_errors, only: error_t
   use mpm_strings, only: str
   use mpm_config, only: config_t, read_config, default_config, write_config_namelist, config_summary, stability_limit
   use mpm_simulation, only: run_result_t, run_simulation, guard_message
   use mpm_output, only: write_run_file
   use mpm_diagnostics, only: status_ok
   use mpm_version, only: code_version
   use mpm_cli_help, only: print_help, print_parameters
   use mpm_sweep, only: sweep_t, read_sweep, run_sweep, has_sweep_group, case_config
   use mpm_sweep_output, only: write_sweep_file, merge_sweep_files
   implicit none

   type(config_t) :: config
   type(run_result_t) :: result
   type(error_t), allocatable :: error
   character(len=:), allocatable :: input
   integer :: nargs

   nargs = command_argument_count()
   if (nargs >= 1) then
      input = argument(1)
      select case (input)
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
         stop
      end select
      if (input(1:1) == '-') call fail("unknown option '"//input//"'; see mpm1d --help", 2)
      if (has_sweep_group(input)) then
         call sweep_command(input)
         stop
      end if
      if (nargs > 1) call fail('too many arguments for a single run; usage: mpm1d [input.nml] (see mpm1d --help)', 2)
      call read_config(input, config, error)
      if (allocated(error)) call fail('invalid input:'//new_line('a')//error%message, 2)
   else
      config = default_config()
      write (output_unit, '(a)') 'mpm1d: no input file given; running the built-in verification case '// &
         '(see mpm1d --help for the namelist reference)'
   end if

   call warn_stability(config%scheme, config%particles_per_element, config%dt_fraction, 1, config%shape)
   write (output_unit, '(a)') '# configuration used:'
   call write_config_namelist(output_unit, config)
   write (output_unit, '(a)') '# '//config_summary(config)

   call run_simulation(config, result, error, record_history=config%history)
   if (allocated(error)) call fail(error%message, 3)
   call write_run_file(config, result, error)
   if (allocated(error)) call fail(error%message, 3)

   write (output_unit, '(a)') 'max |u_cm - u_cm,exact| = '//str(result%max_error)//' m ('// &
      str(100*result%relative_error)//' % of the exact amplitude '//str(result%ucm_amplitude)//' m)'
   write (output_unit, '(a)') 'steps '//str(result%steps_done)//' of '//str(result%steps)//', run time '// &
      str(result%run_time)//' s, '//str(real(result%particles, dp)*result%steps_done/max(result%run_time, 1.0e-9_dp))// &
      ' particle-steps/s'
   write (output_unit, '(a)') 'wrote '//trim(config%file)
   if (result%status /= status_ok) call fail(guard_message(result%status, result%trip, config)//new_line('a')// &
                                             'the history up to that step is in '// &
                                             trim(config%file), 1)

contains

   !> `mpm1d input.nml [--shard I/N] [--threads N]` for an input with a &sweep group.
   subroutine sweep_command(path)
      character(len=*), intent(in) :: path
      type(sweep_t) :: sweep
      integer :: i, shard, shards, threads, failed, above
      character(len=:), allocatable :: option, output
      shard = 0
      shards = 0
      threads = -1
      i = 2
      do while (i <= nargs)
         option = argument(i)
         if (i == nargs) call fail("option '"//option//"' needs a value; see mpm1d --help", 2)
         select case (option)
         case ('--shard')
            call parse_shard(argument(i + 1), shard, shards)
         case ('--threads')
            threads = to_int(argument(i + 1), '--threads')
            if (threads < 0) call fail('--threads '//argument(i + 1)//' is out of range; allowed: 0 (all) or more', 2)
         case default
            call fail("unknown option '"//option//"'; see mpm1d --help", 2)
         end select
         i = i + 2
      end do
      call read_sweep(path, sweep, error, shard, shards, threads)
      if (allocated(error)) call fail('invalid input:'//new_line('a')//error%message, 2)
      output = trim(sweep%base%file)
      if (sweep%settings%shards > 1) output = shard_file(output, sweep%settings%shard, sweep%settings%shards)
      if (sweep%settings%shards > 1) then
         write (output_unit, '(a)') 'mpm1d: sweep shard '//str(sweep%settings%shard)//' of '// &
            str(sweep%settings%shards)//': '//str(size(sweep%cases))//' of '//str(sweep%total_cases)//' cases'
      else
         write (output_unit, '(a)') 'mpm1d: sweep of '//str(size(sweep%cases))//' cases'
      end if
      above = 0
      do i = 1, size(sweep%cases)
         config = case_config(sweep, sweep%cases(i))
         if (config%dt_fraction > stability_limit(config%scheme, config%particles_per_element, config%shape)) &
            above = above + 1
      end do
      if (above > 0) write (error_unit, '(a)') 'mpm1d: warning: '//str(above)//' cases ask for a time step '// &
         'above their scheme''s linear stability limit (see studies/stability); guards will stop them if they grow'
      call run_sweep(sweep)
      call write_sweep_file(output, sweep, error)
      if (allocated(error)) call fail(error%message, 3)
      failed = count(sweep%cases%status /= status_ok)
      write (output_unit, '(a)') 'error pass '//str(sweep%error_pass_time)//' s on '//str(sweep%threads_used)// &
         ' threads; timing pass '//str(sweep%timing_pass_time)//' s on '//str(sweep%settings%timing_threads)// &
         ' threads (min_time '//str(sweep%settings%min_time)//' s per case)'
      write (output_unit, '(a)') str(size(sweep%cases) - failed)//' cases completed, '//str(failed)// &
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
         str(dt_fraction)//' is above the linear stability limit of '//trim(scheme)//' with '// &
         str(particles_per_element)//' particles per element'//which//' (about '//str(nint(limit*1000)/1000.0_dp)// &
         ' of dx/c; see studies/stability and studies/shapes); a guard will stop the run if it grows'
   end subroutine warn_stability

   !> `mpm1d merge OUT.h5 SHARD.h5 ...`
   subroutine merge_command()
      character(len=1024), allocatable :: inputs(:)
      integer :: i
      if (nargs < 3) call fail('usage: mpm1d merge OUT.h5 SHARD1.h5 [SHARD2.h5 ...]', 2)
      allocate (inputs(nargs - 2))
      do i = 3, nargs
         inputs(i - 2) = argument(i)
      end do
      call merge_sweep_files(argument(2), inputs, error)
      if (allocated(error)) call fail(error%message, 2)
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
      character(len=32) :: suffix
      integer :: dot
      write (suffix, '("_shard",i3.3,"of",i3.3)') shard, shards
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
