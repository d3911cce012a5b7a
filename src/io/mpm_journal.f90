!> A journal: a file of records appended as work finishes, that survives a kill at any byte (SIGKILL,
!> the OOM killer, a node failure, a full disk). Each record is one write(2) of a framed payload with a
!> checksum; a reader keeps the whole records in order and drops a torn last one (mpm_journal_c.c has
!> the format). The writer holds an exclusive lock on the file, which the kernel releases when the
!> process dies. The payloads are the caller's (bytes; a sweep's cases: mpm_sweep).
module mpm_journal
   use, intrinsic :: iso_c_binding, only: c_int, c_char, c_long_long, c_null_char, c_int8_t
   use, intrinsic :: iso_fortran_env, only: int8
   use mpm_errors, only: error_t, set_error
   use mpm_files, only: sibling_name, remove_file
   implicit none
   private
   public :: journal_t, journal_record_t, journal_name, journal_open, journal_append, journal_close, journal_read

   !> An open journal. `failure`: why an append failed (the journal then takes no more: it holds the
   !> records before, whole); `found`: the bytes it held when opened (before keeping `keep` of them).
   type :: journal_t
      integer :: fd = -1
      character(len=:), allocatable :: path
      character(len=:), allocatable :: failure
      integer :: appended = 0
      integer(c_long_long) :: found = 0
   end type journal_t

   !> One record read back: its kind and payload.
   type :: journal_record_t
      integer :: kind = 0
      integer(int8), allocatable :: payload(:)
   end type journal_record_t

   interface
      integer(c_int) function c_journal_open(path, keep, found, cause, size) bind(C, name='mpm_journal_open')
         import :: c_int, c_char, c_long_long
         character(kind=c_char), dimension(*), intent(in) :: path
         integer(c_long_long), value :: keep
         integer(c_long_long), intent(out) :: found
         character(kind=c_char), dimension(*), intent(out) :: cause
         integer(c_int), value :: size
      end function c_journal_open
      integer(c_int) function c_journal_append(fd, kind, payload, length, cause, size) bind(C, name='mpm_journal_append')
         import :: c_int, c_char, c_long_long, c_int8_t
         integer(c_int), value :: fd, kind
         integer(c_int8_t), dimension(*), intent(in) :: payload
         integer(c_long_long), value :: length
         character(kind=c_char), dimension(*), intent(out) :: cause
         integer(c_int), value :: size
      end function c_journal_append
      subroutine c_journal_close(fd, keep) bind(C, name='mpm_journal_close')
         import :: c_int
         integer(c_int), value :: fd, keep
      end subroutine c_journal_close
      integer(c_long_long) function c_journal_record(data, n, offset, kind, length) bind(C, name='mpm_journal_record')
         import :: c_int, c_long_long, c_int8_t
         integer(c_int8_t), dimension(*), intent(in) :: data
         integer(c_long_long), value :: n, offset
         integer(c_int), intent(out) :: kind
         integer(c_long_long), intent(out) :: length
      end function c_journal_record
   end interface

contains

   !> The journal of output file `path`: `path`.journal (its last part shortened to 255 characters).
   function journal_name(path) result(name)
      character(len=*), intent(in) :: path
      character(len=:), allocatable :: name
      name = sibling_name(path, '.journal')
   end function journal_name

   !> Open journal `path` for appending, keeping its first `keep` bytes (0: empty). `in_use` is true (and
   !> nothing opened) when another process holds it; `error` when it cannot be opened.
   subroutine journal_open(journal, path, keep, in_use, error)
      type(journal_t), intent(out) :: journal
      character(len=*), intent(in) :: path
      integer(c_long_long), intent(in) :: keep
      logical, intent(out) :: in_use
      type(error_t), allocatable, intent(out) :: error
      character(kind=c_char, len=256) :: cause
      journal%path = path
      journal%fd = c_journal_open(path//c_null_char, keep, journal%found, cause, int(len(cause), c_int))
      in_use = journal%fd == -2
      if (journal%fd == -1) call set_error(error, "cannot open the journal '"//path//"': "//text(cause))
      if (journal%fd < 0) journal%fd = -1
   end subroutine journal_open

   !> Append a record (nothing once an append has failed, or when the journal is not open).
   subroutine journal_append(journal, kind, payload)
      type(journal_t), intent(inout) :: journal
      integer, intent(in) :: kind
      integer(int8), intent(in) :: payload(:)
      character(kind=c_char, len=256) :: cause
      if (journal%fd < 0 .or. allocated(journal%failure)) return
      if (c_journal_append(int(journal%fd, c_int), int(kind, c_int), payload, size(payload, kind=c_long_long), &
                           cause, int(len(cause), c_int)) == 0) then
         journal%appended = journal%appended + 1
      else
         journal%failure = text(cause)
      end if
   end subroutine journal_append

   !> Close the journal (releasing its lock); `remove`: delete the file too (its work is in the output).
   subroutine journal_close(journal, remove)
      type(journal_t), intent(inout) :: journal
      logical, intent(in) :: remove
      if (journal%fd < 0) return
      ! (removed while still locked: no other process takes it over in between)
      if (remove) call remove_file(journal%path)
      call c_journal_close(int(journal%fd, c_int), merge(0_c_int, 1_c_int, remove))
      journal%fd = -1
   end subroutine journal_close

   !> Read the whole records of journal `path`, in order; `valid` is the bytes they take, `torn` the bytes
   !> after them (a record cut short by a kill or a full disk: dropped, never read).
   subroutine journal_read(path, records, valid, torn, error)
      character(len=*), intent(in) :: path
      type(journal_record_t), allocatable, intent(out) :: records(:)
      integer(c_long_long), intent(out) :: valid, torn
      type(error_t), allocatable, intent(out) :: error
      integer(int8), allocatable :: data(:)
      type(journal_record_t), allocatable :: grown(:)
      integer(c_long_long) :: next, length, size_bytes
      integer(c_int) :: kind
      integer :: unit, stat, count
      character(len=256) :: message
      valid = 0
      torn = 0
      open (newunit=unit, file=path, access='stream', form='unformatted', action='read', status='old', &
            iostat=stat, iomsg=message)
      if (stat /= 0) then
         allocate (records(0))
         call set_error(error, "cannot read the journal '"//path//"': "//trim(message))
         return
      end if
      inquire (unit=unit, size=size_bytes)
      allocate (data(max(size_bytes, 0_c_long_long)))
      if (size_bytes > 0) read (unit, iostat=stat, iomsg=message) data
      close (unit)
      if (stat /= 0) then
         allocate (records(0))
         call set_error(error, "cannot read the journal '"//path//"': "//trim(message))
         return
      end if
      count = 0
      allocate (records(16))
      do
         next = c_journal_record(data, size(data, kind=c_long_long), valid, kind, length)
         if (next < 0) exit
         if (count == size(records)) then
            allocate (grown(2*count))
            grown(1:count) = records
            call move_alloc(grown, records)
         end if
         count = count + 1
         records(count)%kind = kind
         records(count)%payload = data(valid + 17:valid + 16 + length)
         valid = next
      end do
      records = records(1:count)
      torn = size(data, kind=c_long_long) - valid
   end subroutine journal_read

   !> The NUL-terminated text in `buffer`.
   function text(buffer) result(t)
      character(kind=c_char, len=*), intent(in) :: buffer
      character(len=:), allocatable :: t
      integer :: n
      n = index(buffer, c_null_char) - 1
      if (n < 0) n = len_trim(buffer)
      t = buffer(1:n)
   end function text
end module mpm_journal
