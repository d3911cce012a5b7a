!> In-house test helpers that need nothing above the core (a test of any layer may use them): counted
!> checks in named cases that run alone, a fixed random seed, scratch files, and running the mpm1d
!> executable. The helpers that run simulations are in mpm_testing_runs.
!>
!> A test program names its cases and runs each one the tester selects:
!>
!>     t = tester('test_example')
!>     if (t%case('partition_of_unity')) call partition_of_unity()
!>     if (t%case('large_runs', long=.true.)) call large_runs()
!>     call t%finish()
!>
!> Its command line (`fpm test test_example -- CASE ...`): case names run those cases only (a long
!> case too); `--list` lists the cases and runs none; no name runs every case but the long ones, which
!> run when the environment variable MPM1D_LONG_TESTS is 1 (the second tier). A name that is no case
!> is an error (exit status 2) that lists the cases.
module mpm_testing
   use, intrinsic :: iso_fortran_env, only: error_unit
   use mpm_kinds, only: dp
   use mpm_strings, only: str
   implicit none
   private
   public :: tester_t, tester, long_variable
   public :: app_path, run_app, read_text, scratch_dir, write_lines, fixed_seed

   !> The environment variable that runs the long cases without naming them: 1 runs them, 0 or unset not.
   character(len=*), parameter :: long_variable = 'MPM1D_LONG_TESTS'

   type :: name_t
      character(len=:), allocatable :: text
   end type name_t

   !> Counts checks and failures, per case and for the program; `finish` prints "NAME: N passed, M
   !> failed" (", K skipped" for long cases left out) and exits with status 1 on a failure. Made by
   !> `tester`, which reads the case names and options of the command line.
   type :: tester_t
      character(len=:), allocatable :: name
      integer :: passed = 0
      integer :: failed = 0
      integer :: skipped = 0
      type(name_t), allocatable :: asked(:)
      logical, allocatable :: asked_met(:)
      type(name_t), allocatable :: cases(:)
      logical, allocatable :: long_case(:)
      logical :: listing = .false.
      logical :: long_runs = .false.
      character(len=:), allocatable :: current
      integer :: case_passed = 0
      integer :: case_failed = 0
   contains
      procedure :: case => tester_case
      procedure :: check => tester_check
      procedure :: check_close => tester_check_close
      procedure :: check_contains => tester_check_contains
      procedure :: finish => tester_finish
   end type tester_t

contains

   !> The tester of test program `name`, with the case names and options of its command line and
   !> MPM1D_LONG_TESTS read; an unknown option or a value of MPM1D_LONG_TESTS other than 0 or 1 ends
   !> the program (exit status 2) with a message naming it.
   function tester(name) result(t)
      character(len=*), intent(in) :: name
      type(tester_t) :: t
      character(len=:), allocatable :: argument, long_value
      integer :: i
      t%name = name
      t%current = ''
      allocate (t%asked(0), t%asked_met(0), t%cases(0), t%long_case(0))
      do i = 1, command_argument_count()
         argument = command_text(i)
         if (argument == '--list') then
            t%listing = .true.
         else if (argument(1:min(1, len(argument))) == '-' .or. len(argument) == 0) then
            call usage_error(name, "unknown option '"//argument//"' (allowed: case names, --list)")
         else
            t%asked = [t%asked, name_t(argument)]
            t%asked_met = [t%asked_met, .false.]
         end if
      end do
      long_value = environment_text(long_variable)
      select case (long_value)
      case ('', '0')
         t%long_runs = .false.
      case ('1')
         t%long_runs = .true.
      case default
         call usage_error(name, long_variable//" is '"//long_value//"' (allowed: 1 runs the long cases, 0 or unset not)")
      end select
   end function tester

   !> Starts case `name` (ending the one before) and says whether it is to run: the names on the
   !> command line, else every case but a long one (`long`) unless MPM1D_LONG_TESTS is 1. A case that
   !> runs starts from the fixed random seed, so that it checks the same inputs alone or with the others.
   logical function tester_case(self, name, long) result(run)
      class(tester_t), intent(inout) :: self
      character(len=*), intent(in) :: name
      logical, intent(in), optional :: long
      logical :: is_long
      integer :: i
      call end_case(self)
      is_long = .false.
      if (present(long)) is_long = long
      do i = 1, size(self%cases)
         if (self%cases(i)%text == name) call usage_error(self%name, "two cases are named '"//name//"'")
      end do
      self%cases = [self%cases, name_t(name)]
      self%long_case = [self%long_case, is_long]
      run = .false.
      if (self%listing) return
      if (size(self%asked) > 0) then
         do i = 1, size(self%asked)
            if (self%asked(i)%text == name) then
               self%asked_met(i) = .true.
               run = .true.
            end if
         end do
      else if (is_long .and. .not. self%long_runs) then
         self%skipped = self%skipped + 1
         print '(a)', '  '//name//': skipped (a long case: '//long_variable//'=1 or its name runs it)'
      else
         run = .true.
      end if
      if (run) then
         self%current = name
         self%case_passed = self%passed
         self%case_failed = self%failed
         call fixed_seed()
      end if
   end function tester_case

   !> Ends the running case, if any: prints its counts; a case that made no check has failed.
   subroutine end_case(self)
      class(tester_t), intent(inout) :: self
      integer :: passed, failed
      if (len(self%current) == 0) return
      passed = self%passed - self%case_passed
      failed = self%failed - self%case_failed
      if (passed + failed == 0) then
         self%failed = self%failed + 1
         failed = 1
         print '(a)', 'FAIL '//self%current//': the case made no check'
      end if
      print '(a)', '  '//self%current//': '//str(passed)//' passed, '//str(failed)//' failed'
      self%current = ''
   end subroutine end_case

   subroutine tester_check(self, label, condition, detail)
      class(tester_t), intent(inout) :: self
      character(len=*), intent(in) :: label
      logical, intent(in) :: condition
      character(len=*), intent(in), optional :: detail
      character(len=:), allocatable :: where
      if (condition) then
         self%passed = self%passed + 1
      else
         self%failed = self%failed + 1
         where = ''
         if (len(self%current) > 0) where = self%current//': '
         if (present(detail)) then
            print '(a)', 'FAIL '//where//label//': '//detail
         else
            print '(a)', 'FAIL '//where//label
         end if
      end if
   end subroutine tester_check

   !> |actual - expected| <= atol + rtol |expected|.
   subroutine tester_check_close(self, label, actual, expected, rtol, atol)
      class(tester_t), intent(inout) :: self
      character(len=*), intent(in) :: label
      real(dp), intent(in) :: actual, expected
      real(dp), intent(in), optional :: rtol, atol
      real(dp) :: r, a
      r = 0.0_dp
      a = 0.0_dp
      if (present(rtol)) r = rtol
      if (present(atol)) a = atol
      call self%check(label, abs(actual - expected) <= a + r*abs(expected), &
                      'actual '//str(actual)//', expected '//str(expected)//' (rtol '//str(r)//', atol '//str(a)//')')
   end subroutine tester_check_close

   subroutine tester_check_contains(self, label, text, part)
      class(tester_t), intent(inout) :: self
      character(len=*), intent(in) :: label, text, part
      call self%check(label, index(text, part) > 0, "'"//part//"' not found in: "//text)
   end subroutine tester_check_contains

   !> Ends the last case; with --list prints the cases (a long one marked), else the program's counts.
   !> A name on the command line that no case has ends the program with exit status 2 and the list.
   subroutine tester_finish(self)
      class(tester_t), intent(inout) :: self
      character(len=:), allocatable :: names
      integer :: i
      call end_case(self)
      names = ''
      do i = 1, size(self%cases)
         names = names//merge(', ', '  ', i > 1)//self%cases(i)%text
         if (self%long_case(i)) names = names//' (long)'
      end do
      names = adjustl(names)
      do i = 1, size(self%asked)
         if (.not. self%asked_met(i)) then
            call usage_error(self%name, "no case is named '"//self%asked(i)%text//"'; its cases: "//trim(names))
         end if
      end do
      if (self%listing) then
         do i = 1, size(self%cases)
            print '(a)', self%cases(i)%text//trim(merge(' (long)', '       ', self%long_case(i)))
         end do
         return
      end if
      if (self%skipped > 0) then
         print '(a)', self%name//': '//str(self%passed)//' passed, '//str(self%failed)//' failed, '// &
            str(self%skipped)//' skipped'
      else
         print '(a)', self%name//': '//str(self%passed)//' passed, '//str(self%failed)//' failed'
      end if
      if (self%failed > 0) stop 1, quiet=.true.  ! (the failures are printed: no backtrace after them)
   end subroutine tester_finish

   !> Ends the test program with exit status 2 and `message`, prefixed with the program's name.
   subroutine usage_error(name, message)
      character(len=*), intent(in) :: name, message
      write (error_unit, '(a)') name//': '//message
      stop 2, quiet=.true.
   end subroutine usage_error

   !> Command-line argument `i`, whole.
   function command_text(i) result(text)
      integer, intent(in) :: i
      character(len=:), allocatable :: text
      integer :: length
      call get_command_argument(i, length=length)
      allocate (character(len=length) :: text)
      if (length > 0) call get_command_argument(i, text)
   end function command_text

   !> The value of environment variable `name` ('' when unset).
   function environment_text(name) result(text)
      character(len=*), intent(in) :: name
      character(len=:), allocatable :: text
      integer :: length, status
      call get_environment_variable(name, length=length, status=status)
      if (status /= 0 .or. length == 0) then
         text = ''
         return
      end if
      allocate (character(len=length) :: text)
      call get_environment_variable(name, text)
   end function environment_text

   !> A fixed seed for random_number (gfortran seeds it from the operating system otherwise): a test
   !> with random inputs then checks the same inputs in every run, and a failure can be reproduced.
   subroutine fixed_seed()
      integer :: n, i
      call random_seed(size=n)
      call random_seed(put=[(104729*i + 7919, i=1, n)])
   end subroutine fixed_seed
   !> Path of the mpm1d executable built with the same profile as this test
   !> (fpm puts tests in <build>/test/ and executables in <build>/app/).
   function app_path() result(path)
      character(len=:), allocatable :: path
      character(len=4096) :: self_path
      integer :: slash
      call get_command_argument(0, self_path)
      slash = index(self_path, '/test/', back=.true.)
      if (slash == 0) then
         path = 'mpm1d'
      else
         path = self_path(1:slash)//'app/mpm1d'
         if (path(1:1) /= '/') path = current_dir()//'/'//path
      end if
   end function app_path

   function current_dir() result(dir)
      use, intrinsic :: iso_c_binding, only: c_char, c_size_t, c_ptr, c_null_char
      character(len=:), allocatable :: dir
      interface
         type(c_ptr) function c_getcwd(buffer, size) bind(C, name='getcwd')
            import :: c_char, c_size_t, c_ptr
            character(kind=c_char), intent(out) :: buffer(*)
            integer(c_size_t), value :: size
         end function c_getcwd
      end interface
      character(kind=c_char) :: buffer(4096)
      type(c_ptr) :: ignored
      integer :: i
      ignored = c_getcwd(buffer, size(buffer, kind=c_size_t))
      dir = ''
      do i = 1, size(buffer)
         if (buffer(i) == c_null_char) exit
         dir = dir//buffer(i)
      end do
   end function current_dir

   !> Run `mpm1d arguments` in folder `dir`; returns the exit status and standard error + output text.
   subroutine run_app(dir, arguments, exit_status, output)
      character(len=*), intent(in) :: dir, arguments
      integer, intent(out) :: exit_status
      character(len=:), allocatable, intent(out) :: output
      integer :: cmdstat
      call execute_command_line('cd '//dir//' && '//app_path()//' '//arguments//' > app_output.txt 2>&1', &
                                exitstat=exit_status, cmdstat=cmdstat)
      if (cmdstat /= 0) exit_status = -999
      output = read_text(dir//'/app_output.txt')
   end subroutine run_app

   !> The whole content of a text file ('' when it cannot be read).
   function read_text(path) result(text)
      character(len=*), intent(in) :: path
      character(len=:), allocatable :: text
      integer :: unit, stat, size_bytes
      text = ''
      open (newunit=unit, file=path, access='stream', form='unformatted', status='old', action='read', iostat=stat)
      if (stat /= 0) return
      inquire (unit=unit, size=size_bytes)
      if (size_bytes > 0) then
         deallocate (text)
         allocate (character(len=size_bytes) :: text)
         read (unit, iostat=stat) text
      end if
      close (unit)
   end function read_text

   !> Write `lines` (each trimmed) to the text file `path`, replacing it.
   subroutine write_lines(path, lines)
      character(len=*), intent(in) :: path, lines(:)
      integer :: unit, i
      open (newunit=unit, file=path, status='replace', action='write')
      do i = 1, size(lines)
         write (unit, '(a)') trim(lines(i))
      end do
      close (unit)
   end subroutine write_lines

   !> A fresh empty folder for a test's files under build/ (so tests leave the source tree clean).
   function scratch_dir(name) result(dir)
      character(len=*), intent(in) :: name
      character(len=:), allocatable :: dir
      dir = 'build/test_scratch/'//name
      call execute_command_line('rm -rf '//dir//' && mkdir -p '//dir)
   end function scratch_dir
end module mpm_testing
