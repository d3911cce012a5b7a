!> File-system helpers through the C library: atomic rename and removal, used so that a run
!> never leaves a partial file under its final name; absolute paths; and the signals SIGINT, SIGTERM
!> and SIGHUP, which end a run (removing its partial file) or, caught by a sweep, stop it so that it
!> writes what it finished (mpm_files_c.c).
module mpm_files
   use, intrinsic :: iso_c_binding, only: c_int, c_char, c_null_char
   implicit none
   private
   public :: rename_file, remove_file, file_exists, available_memory, path_kind, same_file, process_id
   public :: register_partial, forget_partial, pause_seconds, absolute_path, sibling_name
   public :: catch_interrupts, release_interrupts, interrupt_signal, wait_for_signal, file_size_errors
   !> What path_kind returns: nothing there, a regular file, a folder, anything else (device, FIFO, ...).
   integer, parameter, public :: path_none = 0, path_regular = 1, path_folder = 2, path_other = 3

   interface
      integer(c_int) function c_rename(old, new) bind(C, name='rename')
         import :: c_int, c_char
         character(kind=c_char), dimension(*), intent(in) :: old, new
      end function c_rename
      integer(c_int) function c_unlink(path) bind(C, name='unlink')
         import :: c_int, c_char
         character(kind=c_char), dimension(*), intent(in) :: path
      end function c_unlink
      integer(c_int) function c_path_kind(path) bind(C, name='mpm_path_kind')
         import :: c_int, c_char
         character(kind=c_char), dimension(*), intent(in) :: path
      end function c_path_kind
      integer(c_int) function c_same_file(a, b) bind(C, name='mpm_same_file')
         import :: c_int, c_char
         character(kind=c_char), dimension(*), intent(in) :: a, b
      end function c_same_file
      integer(c_int) function c_getpid() bind(C, name='getpid')
         import :: c_int
      end function c_getpid
      integer(c_int) function c_register_partial(path) bind(C, name='mpm_register_partial')
         import :: c_int, c_char
         character(kind=c_char), dimension(*), intent(in) :: path
      end function c_register_partial
      subroutine forget_partial() bind(C, name='mpm_forget_partial')
      end subroutine forget_partial
      integer(c_int) function c_sleep(seconds) bind(C, name='sleep')
         import :: c_int
         integer(c_int), value :: seconds
      end function c_sleep
      integer(c_int) function c_absolute_path(path, out, size) bind(C, name='mpm_absolute_path')
         import :: c_int, c_char
         character(kind=c_char), dimension(*), intent(in) :: path
         character(kind=c_char), dimension(*), intent(out) :: out
         integer(c_int), value :: size
      end function c_absolute_path
      !> From now on the first SIGINT, SIGTERM or SIGHUP is only recorded (interrupt_signal); a
      !> second one ends the process at once, removing the partial file (see mpm_files_c.c).
      subroutine catch_interrupts() bind(C, name='mpm_catch_interrupts')
      end subroutine catch_interrupts
      !> Back to the default: SIGINT, SIGTERM or SIGHUP ends the process (removing the partial file).
      subroutine release_interrupts() bind(C, name='mpm_release_interrupts')
      end subroutine release_interrupts
      !> From now on a write beyond the file-size limit (ulimit -f) fails (EFBIG: the writer reports it,
      !> naming the file) instead of killing the process with SIGXFSZ.
      subroutine file_size_errors() bind(C, name='mpm_file_size_errors')
      end subroutine file_size_errors
      integer(c_int) function c_interrupt_signal() bind(C, name='mpm_interrupt_signal')
         import :: c_int
      end function c_interrupt_signal
      subroutine c_wait_for_signal(seconds, marker) bind(C, name='mpm_wait_for_signal')
         import :: c_int, c_char
         integer(c_int), value :: seconds
         character(kind=c_char), dimension(*), intent(in) :: marker
      end subroutine c_wait_for_signal
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

   !> What `path` names: path_none, path_regular, path_folder or path_other.
   integer function path_kind(path)
      character(len=*), intent(in) :: path
      path_kind = c_path_kind(trim(path)//c_null_char)
   end function path_kind

   !> Do `a` and `b` both exist and name the same file (whatever the spelling of the paths)?
   logical function same_file(a, b)
      character(len=*), intent(in) :: a, b
      same_file = c_same_file(trim(a)//c_null_char, trim(b)//c_null_char) == 1
   end function same_file

   !> Remove `path` (this process's partial output file) if SIGINT, SIGTERM or SIGHUP ends the process
   !> before forget_partial is called (see mpm_files_c.c). Register before creating the file.
   subroutine register_partial(path)
      character(len=*), intent(in) :: path
      integer(c_int) :: stat
      stat = c_register_partial(trim(path)//c_null_char)
   end subroutine register_partial

   !> Sleep `seconds` (test hooks).
   subroutine pause_seconds(seconds)
      integer, intent(in) :: seconds
      integer(c_int) :: left
      left = c_sleep(int(seconds, c_int))
   end subroutine pause_seconds

   !> The signal recorded since catch_interrupts (2 SIGINT, 15 SIGTERM, 1 SIGHUP), 0 if none. Cheap
   !> (reads one flag): a run's time loop asks once per step.
   integer function interrupt_signal()
      interrupt_signal = c_interrupt_signal()
   end function interrupt_signal

   !> Test hooks: create the empty file `marker` (a test waits for it), then sleep until catch_interrupts'
   !> signal arrives, at most `seconds`.
   subroutine wait_for_signal(seconds, marker)
      integer, intent(in) :: seconds
      character(len=*), intent(in) :: marker
      call c_wait_for_signal(int(seconds, c_int), marker//c_null_char)
   end subroutine wait_for_signal

   !> The absolute path of `path` (symbolic links and '..' resolved); for a file not there yet, its
   !> folder's absolute path and its name. `path` itself when that cannot be found.
   function absolute_path(path) result(absolute)
      character(len=*), intent(in) :: path
      character(len=:), allocatable :: absolute
      character(kind=c_char, len=8192) :: buffer
      integer :: n
      n = c_absolute_path(trim(path)//c_null_char, buffer, int(len(buffer), c_int))
      if (n < 0) then
         absolute = trim(path)
      else
         absolute = buffer(1:n)
      end if
   end function absolute_path

   !> The name of a file kept beside `path` (its temporary file, its journal): `path` + `suffix`, its last
   !> component shortened to the file system's 255 characters when it would exceed them (a legal
   !> 255-character name keeps a legal sibling name).
   function sibling_name(path, suffix) result(name)
      character(len=*), intent(in) :: path, suffix
      character(len=:), allocatable :: name
      integer, parameter :: name_max = 255
      integer :: slash
      slash = index(path, '/', back=.true.)
      if (len(path) - slash + len(suffix) <= name_max) then
         name = path//suffix
      else
         name = path(1:slash + name_max - len(suffix))//suffix
      end if
   end function sibling_name

   !> This process's id (unique among the processes running now).
   integer function process_id()
      process_id = c_getpid()
   end function process_id

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
