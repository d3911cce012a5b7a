!> File-system helpers through the C library: atomic rename and removal, used so that a run
!> never leaves a partial file under its final name.
module mpm_files
   use, intrinsic :: iso_c_binding, only: c_int, c_char, c_null_char
   implicit none
   private
   public :: rename_file, remove_file, file_exists, available_memory

   interface
      integer(c_int) function c_rename(old, new) bind(C, name='rename')
         import :: c_int, c_char
         character(kind=c_char), dimension(*), intent(in) :: old, new
      end function c_rename
      integer(c_int) function c_unlink(path) bind(C, name='unlink')
         import :: c_int, c_char
         character(kind=c_char), dimension(*), intent(in) :: path
      end function c_unlink
   end interface

contains

   !> Rename `old` to `new` (atomic within one file system); `ok` is false on failure.
   subroutine rename_file(old, new, ok)
      character(len=*), intent(in) :: old, new
      logical, intent(out) :: ok
      ok = c_rename(trim(old)//c_null_char, trim(new)//c_null_char) == 0
   end subroutine rename_file

   !> Remove `path` if it exists (no error when it does not).
   subroutine remove_file(path)
      character(len=*), intent(in) :: path
      integer(c_int) :: stat
      stat = c_unlink(trim(path)//c_null_char)
   end subroutine remove_file

   logical function file_exists(path)
      character(len=*), intent(in) :: path
      inquire (file=trim(path), exist=file_exists)
   end function file_exists

   !> Memory the system can give a new allocation without swapping (MemAvailable of /proc/meminfo),
   !> in bytes; -1 when unknown.
   function available_memory() result(bytes)
      use mpm_kinds, only: i8
      integer(i8) :: bytes
      integer :: unit, stat
      character(len=256) :: line
      integer(i8) :: kib
      bytes = -1
      open (newunit=unit, file='/proc/meminfo', status='old', action='read', iostat=stat)
      if (stat /= 0) return
      do
         read (unit, '(a)', iostat=stat) line
         if (stat /= 0) exit
         if (index(line, 'MemAvailable:') == 1) then
            read (line(14:), *, iostat=stat) kib
            if (stat == 0) bytes = kib*1024
            exit
         end if
      end do
      close (unit)
   end function available_memory
end module mpm_files
