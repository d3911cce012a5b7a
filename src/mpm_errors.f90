!> Error reporting without `stop`: library routines return an allocated `error_t`
!> and the caller returns early; only the application prints and sets the exit code.
module mpm_errors
   implicit none
   private
   public :: error_t, set_error, append_error

   !> One error (possibly several problems, one per line) with a human-readable message.
   type :: error_t
      character(len=:), allocatable :: message
   end type error_t

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
         error%message = error%message//new_line('a')//message
      end if
   end subroutine append_error
end module mpm_errors
