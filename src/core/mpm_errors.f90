!> Error reporting without `stop`: library routines return an allocated `error_t`
!> and the caller returns early; only the application prints and sets the exit code.
module mpm_errors
   implicit none
   private
   public :: error_t, set_error, append_error

   !> One error (possibly several problems, one per line) with a human-readable message.
   type :: error_t
      character(len=:), allocatable :: message
      !> Problems appended so far; after max_problems the rest are counted, not listed (an input of
      !> 20,000 wrong lines is reported at once, not in quadratic time).
      integer :: problems = 1
   end type error_t

   integer, parameter :: max_problems = 100

contains

   !> Allocate `error` with `message` (replaces any earlier content).
   subroutine set_error(error, message)
      type(error_t), allocatable, intent(inout) :: error
      character(len=*), intent(in) :: message
      if (allocated(error)) deallocate (error)
      allocate (error)
      error%message = message
   end subroutine set_error

   !> Add one more problem as a new line of `error`, creating it when absent.
   !> Used by validation, which reports every problem it finds, not just the first.
   subroutine append_error(error, message)
      type(error_t), allocatable, intent(inout) :: error
      character(len=*), intent(in) :: message
      if (.not. allocated(error)) then
         allocate (error)
         error%message = message
      else
         error%problems = error%problems + 1
         if (error%problems <= max_problems) then
            error%message = error%message//new_line('a')//message
         else if (error%problems == max_problems + 1) then
            error%message = error%message//new_line('a')//'(more problems follow; the first 100 are listed)'
         end if
      end if
   end subroutine append_error
end module mpm_errors
