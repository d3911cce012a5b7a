!> mpm1d command line: `mpm1d [input.nml]`, `mpm1d --help`, `mpm1d --version`.
!> Parses arguments, calls the library, prints messages and sets the exit code:
!> 0 success, 1 a guard stopped the run (its history is still written), 2 bad input or usage,
!> 3 output could not be written.
program mpm1d_main
   use, intrinsic :: iso_fortran_env, only: output_unit, error_unit
   use mpm_kinds, only: dp
   use mpm_errors, only: error_t
   use mpm_strings, only: str
   use mpm_config, only: config_t, read_config, default_config, write_config_namelist, config_summary
   use mpm_simulation, only: run_result_t, run_simulation
   use mpm_output, only: write_run_file
   use mpm_diagnostics, only: status_ok
   use mpm_version, only: code_version
   use mpm_cli_help, only: print_help
   implicit none

   type(config_t) :: config
   type(run_result_t) :: result
   type(error_t), allocatable :: error
   character(len=:), allocatable :: input
   integer :: nargs

   nargs = command_argument_count()
   if (nargs > 1) call fail('too many arguments; usage: mpm1d [input.nml] (see mpm1d --help)', 2)
   if (nargs == 1) then
      input = argument(1)
      select case (input)
      case ('-h', '--help')
         call print_help(output_unit)
         stop
      case ('-V', '--version')
         write (output_unit, '(a)') code_version
         stop
      end select
      if (input(1:1) == '-') call fail("unknown option '"//input//"'; see mpm1d --help", 2)
      call read_config(input, config, error)
      if (allocated(error)) call fail('invalid input:'//new_line('a')//error%message, 2)
   else
      config = default_config()
      write (output_unit, '(a)') 'mpm1d: no input file given; running the built-in verification case '// &
         '(see mpm1d --help for the namelist reference)'
   end if

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
   if (result%status /= status_ok) call fail(result%message//new_line('a')//'the history up to that step is in '// &
                                             trim(config%file), 1)

contains

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
