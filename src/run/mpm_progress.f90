!> A progress line for long sweeps on standard error: cases done / total, elapsed time and an
!> estimate of the time remaining, redrawn in place on a terminal. When standard error is not a
!> terminal (a batch job's log), a line of its own every `log_interval` seconds, so that the log of a
!> long sweep shows how far it got; a sweep shorter than that logs nothing.
!> Cases differ in cost by orders of magnitude (a case costs about particles x steps), so the
!> estimate weighs each case by its expected cost, not by its count (remaining_time).
!> `advance` may be called from inside an OpenMP parallel region.
module mpm_progress
   use, intrinsic :: iso_c_binding, only: c_int
   use, intrinsic :: iso_fortran_env, only: error_unit
   use omp_lib, only: omp_get_wtime
   use mpm_kinds, only: dp
   use mpm_strings, only: num
   implicit none
   private
   public :: progress_t, stderr_is_terminal, remaining_time

   !> Seconds between two updates of the line.
   real(dp), parameter :: interval = 0.25_dp
   !> Seconds between two lines in a log (standard error not a terminal).
   real(dp), parameter :: log_interval = 60.0_dp

   type :: progress_t
      character(len=:), allocatable :: label
      integer :: total = 0
      integer :: done = 0
      !> Expected cost of all cases and of those done (any unit; only their ratio is used).
      real(dp) :: total_weight = 0.0_dp
      real(dp) :: done_weight = 0.0_dp
      logical :: shown = .false.
      !> Lines of their own, for a log (standard error not a terminal), and whether one was written.
      logical :: logged = .false., log_written = .false.
      !> Cases done when the last line was drawn (a log's last line is not written twice).
      integer :: drawn = -1
      !> Seconds between two lines of a log: log_interval, or MPM1D_PROGRESS_LOG_SECONDS (a test hook).
      real(dp) :: log_every = log_interval
      real(dp) :: started_at = 0.0_dp
      real(dp) :: last = 0.0_dp
   contains
      procedure :: start => progress_start
      procedure :: advance => progress_advance
      procedure :: finish => progress_finish
   end type progress_t

   interface
      integer(c_int) function c_isatty(fd) bind(C, name='isatty')
         import :: c_int
         integer(c_int), value :: fd
      end function c_isatty
   end interface

contains

   logical function stderr_is_terminal()
      stderr_is_terminal = c_isatty(2_c_int) == 1
   end function stderr_is_terminal

   !> Start a pass over `size(weights)` cases; `weights(i)` is case i's expected cost.
   subroutine progress_start(self, label, weights, wanted)
      class(progress_t), intent(inout) :: self
      character(len=*), intent(in) :: label
      real(dp), intent(in) :: weights(:)
      logical, intent(in) :: wanted
      self%label = label
      self%total = size(weights)
      self%done = 0
      self%total_weight = sum(weights)
      self%done_weight = 0.0_dp
      self%shown = wanted .and. stderr_is_terminal()
      self%logged = wanted .and. .not. self%shown
      self%log_written = .false.
      self%drawn = -1
      self%log_every = log_seconds()
      self%started_at = omp_get_wtime()
      self%last = self%started_at
   end subroutine progress_start

   !> One more case done, of expected cost `weight`; redraw the line at most every `interval` seconds.
   subroutine progress_advance(self, weight)
      class(progress_t), intent(inout) :: self
      real(dp), intent(in) :: weight
      real(dp) :: now
      !$omp atomic update
      self%done = self%done + 1
      !$omp atomic update
      self%done_weight = self%done_weight + weight
      if (.not. (self%shown .or. self%logged)) return
      now = omp_get_wtime()
      if (now - self%last < merge(interval, self%log_every, self%shown)) return
      !$omp critical (mpm_progress_line)
      if (now - self%last >= merge(interval, self%log_every, self%shown)) then
         self%last = now
         call draw(self, now)
      end if
      !$omp end critical (mpm_progress_line)
   end subroutine progress_advance

   !> Seconds between two lines of a log: log_interval unless MPM1D_PROGRESS_LOG_SECONDS gives a number
   !> >= 0 (a test of the log's lines cannot wait a minute).
   real(dp) function log_seconds()
      character(len=32) :: text
      integer :: length, stat
      real(dp) :: value
      log_seconds = log_interval
      call get_environment_variable('MPM1D_PROGRESS_LOG_SECONDS', text, length=length)
      if (length == 0) return
      read (text, *, iostat=stat) value
      if (stat == 0 .and. value >= 0.0_dp) log_seconds = value
   end function log_seconds

   !> Time still needed when cases of expected cost `done_weight` out of `total_weight` took
   !> `elapsed` seconds: the rate so far (cost per second) applied to the cost left. 0 before any
   !> cost is done (nothing to extrapolate from) and when nothing is left.
   pure real(dp) function remaining_time(elapsed, done_weight, total_weight)
      real(dp), intent(in) :: elapsed, done_weight, total_weight
      remaining_time = 0.0_dp
      if (done_weight > 0.0_dp .and. total_weight > done_weight) &
         remaining_time = elapsed*(total_weight - done_weight)/done_weight
   end function remaining_time

   subroutine progress_finish(self)
      class(progress_t), intent(inout) :: self
      if (self%logged .and. self%log_written .and. self%drawn /= self%done) call draw(self, omp_get_wtime())
      if (.not. self%shown) return
      call draw(self, omp_get_wtime())
      write (error_unit, '(a)') ''
   end subroutine progress_finish

   subroutine draw(self, now)
      type(progress_t), intent(inout) :: self
      real(dp), intent(in) :: now
      real(dp) :: elapsed, remaining
      integer :: done
      character(len=32) :: count_text
      character(len=:), allocatable :: line
      done = self%done
      self%drawn = done
      elapsed = now - self%started_at
      remaining = remaining_time(elapsed, self%done_weight, self%total_weight)
      write (count_text, '(i0," / ",i0)') done, self%total
      line = trim(self%label)//': '//trim(count_text)//' cases, '//num(elapsed, 3)//' s elapsed, about '// &
             num(remaining, 3)//' s remaining'
      if (self%shown) then
         write (error_unit, '(a)', advance='no') achar(13)//line//'   '
      else
         write (error_unit, '(a)') line
         self%log_written = .true.
      end if
      flush (error_unit)
   end subroutine draw
end module mpm_progress
