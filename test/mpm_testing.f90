!> In-house test helpers: counted checks and running the mpm1d executable from a test.
module mpm_testing
   use mpm_kinds, only: dp
   use mpm_strings, only: str
   use mpm_simulation, only: run_result_t, run_simulation
   use mpm_config, only: config_t, resolve_config
   use mpm_errors, only: error_t
   use mpm_transfer, only: parallel_threshold
   use omp_lib, only: omp_set_num_threads
   implicit none
   private
   public :: tester_t, app_path, run_app, read_text, scratch_dir, write_lines, fixed_seed
   public :: check_paths_agree
   public :: check_fused_run, check_fused_config, run_resolved

   !> Counts checks and failures; `finish` prints "N passed, M failed" and ends with error stop 1 on failure.
   type :: tester_t
      character(len=:), allocatable :: name
      integer :: passed = 0
      integer :: failed = 0
   contains

      procedure :: check => tester_check
      procedure :: check_close => tester_check_close
      procedure :: check_contains => tester_check_contains
      procedure :: finish => tester_finish
   end type tester_t

contains

   !> A fixed seed for random_number (gfortran seeds it from the operating system otherwise): a test
   !> with random inputs then checks the same inputs in every run, and a failure can be reproduced.
   subroutine fixed_seed()
      integer :: n, i
      call random_seed(size=n)
      call random_seed(put=[(104729*i + 7919, i=1, n)])
   end subroutine fixed_seed

   !> A run on the fused kernels and the same run on the generic path (`kernels='generic'`) agree: the
   !> paths were the ones asked for, same status and steps, u_cm histories equal to round-off and the
   !> last kinetic energies to 1e-10. The tolerance on u_cm is 1e-12 of the exact amplitude plus two
   !> ulps of the body length per particle: u_cm is a mean of x - X with x up to L, so one ulp of one
   !> particle's position moves it by spacing(L)/N, which for few particles and small amplitudes is more
   !> than 1e-12 of the amplitude.
   subroutine check_paths_agree(t, label, fused, generic, length)
      type(tester_t), intent(inout) :: t
      character(len=*), intent(in) :: label
      type(run_result_t), intent(in) :: fused, generic
      real(dp), intent(in) :: length
      real(dp) :: tolerance, worst
      integer :: n
      call t%check(label//'auto chose the fused kernels, generic the generic path', fused%fused .and. .not. generic%fused)
      call t%check(label//'same status and steps', fused%status == generic%status .and. &
                   fused%steps_done == generic%steps_done .and. fused%history%recorded == generic%history%recorded)
      n = min(fused%history%recorded, generic%history%recorded)
      tolerance = 1.0e-12_dp*abs(fused%ucm_amplitude) + 2*spacing(length)/fused%particles
      worst = maxval(abs(fused%history%ucm(0:n - 1) - generic%history%ucm(0:n - 1)))
      call t%check(label//'u_cm histories agree to round-off', worst <= tolerance, &
                   'largest difference '//str(worst)//' m, tolerance '//str(tolerance)//' m')
      call t%check_close(label//'kinetic energy histories', generic%history%kinetic_energy(n - 1), &
                         fused%history%kinetic_energy(n - 1), rtol=1.0e-10_dp)
   end subroutine check_paths_agree

   !> `given`, resolved (its derived quantities from the variables set), run with its history; a run
   !> that cannot start ends the test program (error stop naming the run's error).
   function run_resolved(given) result(res)
      type(config_t), intent(in) :: given
      type(run_result_t) :: res
      type(config_t) :: config
      type(error_t), allocatable :: error
      config = given
      call resolve_config(config)
      call run_simulation(config, res, error, record_history=.true.)
      if (allocated(error)) error stop 'run_resolved: the run failed to start'
   end function run_resolved

   !> The bar (scheme, shape, elements x ppc, dt fraction, amplitude v0, periods) run on the fused
   !> kernels and on the generic path agree: check_fused_config.
   subroutine check_fused_run(t, scheme, shape, elements, ppc, fraction, v0, periods, segments)
      type(tester_t), intent(inout) :: t
      character(len=*), intent(in) :: scheme, shape
      integer, intent(in) :: elements, ppc
      real(dp), intent(in) :: fraction, v0, periods
      logical, intent(in), optional :: segments
      type(config_t) :: config
      config%scheme = scheme
      config%shape = shape
      config%elements = elements
      config%particles_per_element = ppc
      config%dt_fraction = fraction
      config%velocity_amplitude = v0
      config%periods = periods
      call check_fused_config(t, scheme//' '//shape//' '//str(elements)//' x '//str(ppc)//' k '//str(fraction)// &
                              ' v0 '//str(v0)//': ', config, segments)
   end subroutine check_fused_run

   !> `given` run on the fused kernels (1 thread) and on the generic path agree (check_paths_agree). With
   !> `segments`, the run must be large enough to be cut into segments (`parallel_threshold` particles),
   !> and the fused run on 2 threads must give the 1-thread histories of u_cm and the energies bit for bit.
   subroutine check_fused_config(t, label, given, segments)
      type(tester_t), intent(inout) :: t
      character(len=*), intent(in) :: label
      type(config_t), intent(in) :: given
      logical, intent(in), optional :: segments
      type(run_result_t) :: fused, generic, two
      type(config_t) :: config
      type(error_t), allocatable :: error
      config = given
      call resolve_config(config)
      call omp_set_num_threads(1)
      call run_simulation(config, fused, error, record_history=.true.)
      if (allocated(error)) error stop 'check_fused_config: the run failed to start'
      config%kernels = 'generic'
      call run_simulation(config, generic, error, record_history=.true.)
      call check_paths_agree(t, label, fused, generic, maxval(abs(fused%domain)))
      if (.not. present(segments)) return
      if (segments) then
         call t%check(label//'the run is cut into segments', fused%particles >= parallel_threshold)
         config%kernels = 'auto'
         call omp_set_num_threads(2)
         call run_simulation(config, two, error, record_history=.true.)
         call omp_set_num_threads(1)
         call t%check(label//'1 and 2 threads give the same u_cm and energy histories', &
                      two%steps_done == fused%steps_done .and. all(two%history%ucm == fused%history%ucm) .and. &
                      all(two%history%kinetic_energy == fused%history%kinetic_energy) .and. &
                      all(two%history%strain_energy == fused%history%strain_energy))
      end if
   end subroutine check_fused_config

   subroutine tester_check(self, label, condition, detail)
      class(tester_t), intent(inout) :: self
      character(len=*), intent(in) :: label
      logical, intent(in) :: condition
      character(len=*), intent(in), optional :: detail
      if (condition) then
         self%passed = self%passed + 1
      else
         self%failed = self%failed + 1
         if (present(detail)) then
            print '(a)', 'FAIL '//label//': '//detail
         else
            print '(a)', 'FAIL '//label
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

   subroutine tester_finish(self)
      class(tester_t), intent(in) :: self
      print '(a)', self%name//': '//str(self%passed)//' passed, '//str(self%failed)//' failed'
      if (self%failed > 0) error stop 1
   end subroutine tester_finish

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
