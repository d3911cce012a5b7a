!> Small text helpers for messages: numbers to strings, lower case.
module mpm_strings
   use mpm_kinds, only: dp, i8
   implicit none
   private
   public :: str, lower

   !> `str(x)`: the shortest usual text of an integer or real (g0 format).
   interface str
      module procedure str_int, str_int8, str_real
   end interface str

contains

   function str_int(value) result(text)
      integer, intent(in) :: value
      character(len=:), allocatable :: text
      character(len=16) :: buffer
      write (buffer, '(i0)') value
      text = trim(buffer)
   end function str_int

   function str_int8(value) result(text)
      integer(i8), intent(in) :: value
      character(len=:), allocatable :: text
      character(len=24) :: buffer
      write (buffer, '(i0)') value
      text = trim(buffer)
   end function str_int8

   function str_real(value) result(text)
      real(dp), intent(in) :: value
      character(len=:), allocatable :: text
      character(len=40) :: buffer
      write (buffer, '(g0)') value
      text = trim(adjustl(buffer))
   end function str_real

   !> ASCII lower case.
   pure function lower(text) result(low)
      character(len=*), intent(in) :: text
      character(len=len(text)) :: low
      integer :: i, code
      low = text
      do i = 1, len(text)
         code = iachar(text(i:i))
         if (code >= iachar('A') .and. code <= iachar('Z')) low(i:i) = achar(code + 32)
      end do
   end function lower
end module mpm_strings
