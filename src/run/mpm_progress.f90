!> A progress line for long sweeps on standard error: cases done / total, elapsed time and an
!> estimate of the time remaining. Quiet when standard error is not a terminal (logs, CI).
!> Cases differ in cost by orders of magnitude (a case costs about particles x steps), so the
!> estimate weighs each case by its expected cost, not by its count (remaining_time).
!> `advance` may be called from inside an OpenMP parallel region.
module mpm_progress
   use, intrinsic :: iso_c_binding, only: c_int
   use, intrinsic :: iso_fortran_env, only: error_unit
   use omp_lib, only: omp_get_wtime
   use mpm_kinds, only: dp
   implicit none
   private
   public :: progress_t, stderr_is_terminal, remaining_time

   !> Seconds between two updates of the line.
   real(dp), parameter :: interval = 0.25_dp

   type :: progress_t
      character(len=:), allocatable :: label
      integer :: total = 0
      integer :: done = 0
      !> Expected cost of all cases and of those done (any unit; only their ratio is used).
      real(dp) :: total_weight = 0.0_dp
      real(dp) :: done_weight = 0.0_dp
      logical :: shown = .false.
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
      if (.not. self%shown) return
      now = omp_get_wtime()
      if (now - self%last < interval) return
      !$omp critical (mpm_progress_line)
      if (now - self%last >= interval) then
         self%last = now
         call draw(self, now)
      end if
      !$omp end critical (mpm_progress_line)
   end subroutine progress_advance

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
      if (.not. self%shown) return
      call draw(self, omp_get_wtime())
      write (error_unit, '(a)') ''
   end subroutine progress_finish

   subroutine draw(self, now)
      type(progress_t), intent(in) :: self
      real(dp), intent(in) :: now
      real(dp) :: elapsed, remaining
      integer :: done
      character(len=160) :: line
      done = self%done
      elapsed = now - self%started_at
      remaining = remaining_time(elapsed, self%done_weight, self%total_weight)
      write (line, '(a,": ",i0," / ",i0," cases, ",f0.1," s elapsed, about ",f0.1," s remaining")') &
         self%label, done, self%total, elapsed, remaining
      write (error_unit, '(a)', advance='no') achar(13)//trim(line)//'   '
      flush (error_unit)
   end subroutine draw
end module mpm_progress
