!> A run's state as named values: what a checkpoint holds, kept as bytes in the machine's layout (a
!> checkpoint is read back by the build that wrote it). Each part of a run puts its own values under
!> names of its own (`particles.x`, `implicit.solves`) and gets them back by name; an allocatable array
!> that was not allocated is not put, and comes back not allocated. `sync` does either, as `saving`
!> says, so that one list of a part's values serves both ways. A value asked for that is absent,
!> or present with another type or rank, is noted in `missing` (a checkpoint of another build or a
!> corrupt one), never read.
module mpm_state
   use, intrinsic :: iso_fortran_env, only: int8, int32, int64
   use mpm_kinds, only: dp
   implicit none
   private
   public :: state_t, state_item_t

   !> The types of a value.
   integer, parameter, public :: item_real = 1, item_int = 2, item_logical = 3, item_text = 4

   !> One named value: its type, rank (0 scalar, 1, 2), lower bounds and extents, and bytes.
   type :: state_item_t
      character(len=:), allocatable :: name
      integer :: kind = 0, rank = 0
      integer :: lower(2) = 1, extent(2) = 1
      integer(int8), allocatable :: bytes(:)
   end type state_item_t

   type :: state_t
      integer :: count = 0
      type(state_item_t), allocatable :: items(:)
      !> The names asked for and not found as asked (space-separated; '' when every one was).
      character(len=:), allocatable :: missing
      !> What `sync` does: put the values (true), or get them back.
      logical :: saving = .true.
   contains
      procedure :: put_real, put_int, put_logical, put_text, put_reals, put_reals2, put_ints, put_ints2
      generic :: put => put_real, put_int, put_logical, put_text, put_reals, put_reals2, put_ints, put_ints2
      procedure :: get_real, get_int, get_logical, get_text, get_reals, get_reals2, get_ints, get_ints2
      generic :: get => get_real, get_int, get_logical, get_text, get_reals, get_reals2, get_ints, get_ints2
      procedure :: sync_real, sync_int, sync_logical, sync_reals, sync_reals2, sync_ints, sync_ints2
      generic :: sync => sync_real, sync_int, sync_logical, sync_reals, sync_reals2, sync_ints, sync_ints2
      procedure :: has
      procedure :: add
      procedure, nopass :: encode, decode
   end type state_t

contains

   !> Whether the state holds a value named `name`.
   logical function has(self, name)
      class(state_t), intent(in) :: self
      character(len=*), intent(in) :: name
      has = find(self, name) > 0
   end function has

   !> Add an item (replacing one of the same name).
   subroutine add(self, item)
      class(state_t), intent(inout) :: self
      type(state_item_t), intent(in) :: item
      type(state_item_t), allocatable :: grown(:)
      integer :: i
      i = find(self, item%name)
      if (i > 0) then
         self%items(i) = item
         return
      end if
      if (.not. allocated(self%items)) allocate (self%items(64))
      if (self%count == size(self%items)) then
         allocate (grown(2*self%count))
         grown(1:self%count) = self%items(1:self%count)
         call move_alloc(grown, self%items)
      end if
      self%count = self%count + 1
      self%items(self%count) = item
   end subroutine add

   integer function find(self, name)
      type(state_t), intent(in) :: self
      character(len=*), intent(in) :: name
      do find = 1, self%count
         if (self%items(find)%name == name) return
      end do
      find = 0
   end function find

   !> The item `name` if it is there with `kind` and `rank` (else 0, and the name noted as missing).
   integer function lookup(self, name, kind, rank) result(i)
      class(state_t), intent(inout) :: self
      character(len=*), intent(in) :: name
      integer, intent(in) :: kind, rank
      i = find(self, name)
      if (i > 0) then
         if (self%items(i)%kind /= kind .or. self%items(i)%rank /= rank) i = 0
      end if
      if (i > 0) return
      if (.not. allocated(self%missing)) self%missing = ''
      self%missing = trim(self%missing//' '//name)
   end function lookup

   function item_of(name, kind, rank, lower, extent, bytes) result(item)
      character(len=*), intent(in) :: name
      integer, intent(in) :: kind, rank, lower(2), extent(2)
      integer(int8), intent(in) :: bytes(:)
      type(state_item_t) :: item
      item%name = name
      item%kind = kind
      item%rank = rank
      item%lower = lower
      item%extent = extent
      item%bytes = bytes
   end function item_of

   subroutine put_real(self, name, value)
      class(state_t), intent(inout) :: self
      character(len=*), intent(in) :: name
      real(dp), intent(in) :: value
      call self%add(item_of(name, item_real, 0, [1, 1], [1, 1], transfer(value, [0_int8])))
   end subroutine put_real

   subroutine put_int(self, name, value)
      class(state_t), intent(inout) :: self
      character(len=*), intent(in) :: name
      integer, intent(in) :: value
      call self%add(item_of(name, item_int, 0, [1, 1], [1, 1], transfer(value, [0_int8])))
   end subroutine put_int

   subroutine put_logical(self, name, value)
      class(state_t), intent(inout) :: self
      character(len=*), intent(in) :: name
      logical, intent(in) :: value
      call self%add(item_of(name, item_logical, 0, [1, 1], [1, 1], transfer(merge(1, 0, value), [0_int8])))
   end subroutine put_logical

   subroutine put_text(self, name, value)
      class(state_t), intent(inout) :: self
      character(len=*), intent(in) :: name, value
      call self%add(item_of(name, item_text, 0, [1, 1], [len(value), 1], transfer(value, [0_int8], len(value))))
   end subroutine put_text

   subroutine put_reals(self, name, values)
      class(state_t), intent(inout) :: self
      character(len=*), intent(in) :: name
      real(dp), allocatable, intent(in) :: values(:)
      if (.not. allocated(values)) return
      call self%add(item_of(name, item_real, 1, [lbound(values, 1), 1], [size(values), 1], transfer(values, [0_int8])))
   end subroutine put_reals

   subroutine put_reals2(self, name, values)
      class(state_t), intent(inout) :: self
      character(len=*), intent(in) :: name
      real(dp), allocatable, intent(in) :: values(:, :)
      if (.not. allocated(values)) return
      call self%add(item_of(name, item_real, 2, lbound(values), shape(values), transfer(values, [0_int8])))
   end subroutine put_reals2

   subroutine put_ints(self, name, values)
      class(state_t), intent(inout) :: self
      character(len=*), intent(in) :: name
      integer, allocatable, intent(in) :: values(:)
      if (.not. allocated(values)) return
      call self%add(item_of(name, item_int, 1, [lbound(values, 1), 1], [size(values), 1], transfer(values, [0_int8])))
   end subroutine put_ints

   subroutine put_ints2(self, name, values)
      class(state_t), intent(inout) :: self
      character(len=*), intent(in) :: name
      integer, allocatable, intent(in) :: values(:, :)
      if (.not. allocated(values)) return
      call self%add(item_of(name, item_int, 2, lbound(values), shape(values), transfer(values, [0_int8])))
   end subroutine put_ints2

   subroutine get_real(self, name, value)
      class(state_t), intent(inout) :: self
      character(len=*), intent(in) :: name
      real(dp), intent(inout) :: value
      integer :: i
      i = lookup(self, name, item_real, 0)
      if (i > 0) value = transfer(self%items(i)%bytes, value)
   end subroutine get_real

   subroutine get_int(self, name, value)
      class(state_t), intent(inout) :: self
      character(len=*), intent(in) :: name
      integer, intent(inout) :: value
      integer :: i
      i = lookup(self, name, item_int, 0)
      if (i > 0) value = transfer(self%items(i)%bytes, value)
   end subroutine get_int

   subroutine get_logical(self, name, value)
      class(state_t), intent(inout) :: self
      character(len=*), intent(in) :: name
      logical, intent(inout) :: value
      integer :: i
      i = lookup(self, name, item_logical, 0)
      if (i > 0) value = transfer(self%items(i)%bytes, 0) /= 0
   end subroutine get_logical

   subroutine get_text(self, name, value)
      class(state_t), intent(inout) :: self
      character(len=*), intent(in) :: name
      character(len=:), allocatable, intent(inout) :: value
      integer :: i
      i = lookup(self, name, item_text, 0)
      if (i == 0) return
      if (allocated(value)) deallocate (value)
      allocate (character(len=self%items(i)%extent(1)) :: value)
      if (len(value) > 0) value = transfer(self%items(i)%bytes, value)
   end subroutine get_text

   !> An array back as it was put: allocated with its bounds, or not allocated when it was not put.
   subroutine get_reals(self, name, values)
      class(state_t), intent(inout) :: self
      character(len=*), intent(in) :: name
      real(dp), allocatable, intent(inout) :: values(:)
      integer :: i
      if (allocated(values)) deallocate (values)
      i = find(self, name)
      if (i == 0) return ! (not put: it was not allocated)
      i = lookup(self, name, item_real, 1)
      if (i == 0) return
      associate (it => self%items(i))
         allocate (values(it%lower(1):it%lower(1) + it%extent(1) - 1))
         values = transfer(it%bytes, values, it%extent(1))
      end associate
   end subroutine get_reals

   subroutine get_reals2(self, name, values)
      class(state_t), intent(inout) :: self
      character(len=*), intent(in) :: name
      real(dp), allocatable, intent(inout) :: values(:, :)
      integer :: i
      if (allocated(values)) deallocate (values)
      i = find(self, name)
      if (i == 0) return
      i = lookup(self, name, item_real, 2)
      if (i == 0) return
      associate (it => self%items(i))
         allocate (values(it%lower(1):it%lower(1) + it%extent(1) - 1, it%lower(2):it%lower(2) + it%extent(2) - 1))
         values = reshape(transfer(it%bytes, [0.0_dp], it%extent(1)*it%extent(2)), it%extent)
      end associate
   end subroutine get_reals2

   subroutine get_ints(self, name, values)
      class(state_t), intent(inout) :: self
      character(len=*), intent(in) :: name
      integer, allocatable, intent(inout) :: values(:)
      integer :: i
      if (allocated(values)) deallocate (values)
      i = find(self, name)
      if (i == 0) return
      i = lookup(self, name, item_int, 1)
      if (i == 0) return
      associate (it => self%items(i))
         allocate (values(it%lower(1):it%lower(1) + it%extent(1) - 1))
         values = transfer(it%bytes, values, it%extent(1))
      end associate
   end subroutine get_ints

   subroutine get_ints2(self, name, values)
      class(state_t), intent(inout) :: self
      character(len=*), intent(in) :: name
      integer, allocatable, intent(inout) :: values(:, :)
      integer :: i
      if (allocated(values)) deallocate (values)
      i = find(self, name)
      if (i == 0) return
      i = lookup(self, name, item_int, 2)
      if (i == 0) return
      associate (it => self%items(i))
         allocate (values(it%lower(1):it%lower(1) + it%extent(1) - 1, it%lower(2):it%lower(2) + it%extent(2) - 1))
         values = reshape(transfer(it%bytes, [0], it%extent(1)*it%extent(2)), it%extent)
      end associate
   end subroutine get_ints2

   subroutine sync_real(self, name, value)
      class(state_t), intent(inout) :: self
      character(len=*), intent(in) :: name
      real(dp), intent(inout) :: value
      if (self%saving) then
         call self%put(name, value)
      else
         call self%get(name, value)
      end if
   end subroutine sync_real

   subroutine sync_int(self, name, value)
      class(state_t), intent(inout) :: self
      character(len=*), intent(in) :: name
      integer, intent(inout) :: value
      if (self%saving) then
         call self%put(name, value)
      else
         call self%get(name, value)
      end if
   end subroutine sync_int

   subroutine sync_logical(self, name, value)
      class(state_t), intent(inout) :: self
      character(len=*), intent(in) :: name
      logical, intent(inout) :: value
      if (self%saving) then
         call self%put(name, value)
      else
         call self%get(name, value)
      end if
   end subroutine sync_logical

   subroutine sync_reals(self, name, values)
      class(state_t), intent(inout) :: self
      character(len=*), intent(in) :: name
      real(dp), allocatable, intent(inout) :: values(:)
      if (self%saving) then
         call self%put(name, values)
      else
         call self%get(name, values)
      end if
   end subroutine sync_reals

   subroutine sync_reals2(self, name, values)
      class(state_t), intent(inout) :: self
      character(len=*), intent(in) :: name
      real(dp), allocatable, intent(inout) :: values(:, :)
      if (self%saving) then
         call self%put(name, values)
      else
         call self%get(name, values)
      end if
   end subroutine sync_reals2

   subroutine sync_ints(self, name, values)
      class(state_t), intent(inout) :: self
      character(len=*), intent(in) :: name
      integer, allocatable, intent(inout) :: values(:)
      if (self%saving) then
         call self%put(name, values)
      else
         call self%get(name, values)
      end if
   end subroutine sync_ints

   subroutine sync_ints2(self, name, values)
      class(state_t), intent(inout) :: self
      character(len=*), intent(in) :: name
      integer, allocatable, intent(inout) :: values(:, :)
      if (self%saving) then
         call self%put(name, values)
      else
         call self%get(name, values)
      end if
   end subroutine sync_ints2

   !> An item as bytes: the name's length and the name, kind, rank, lower bounds, extents (32-bit
   !> integers), then its bytes.
   function encode(item) result(bytes)
      type(state_item_t), intent(in) :: item
      integer(int8), allocatable :: bytes(:)
      bytes = [transfer(int(len(item%name), int32), [0_int8]), transfer(item%name, [0_int8], len(item%name)), &
               transfer(int([item%kind, item%rank, item%lower, item%extent], int32), [0_int8]), item%bytes]
   end function encode

   !> The item `bytes` encode; `ok` false when they are not one (too short, a negative length, a size
   !> that does not match its extents).
   subroutine decode(bytes, item, ok)
      integer(int8), intent(in) :: bytes(:)
      type(state_item_t), intent(out) :: item
      logical, intent(out) :: ok
      integer(int32) :: n, head(6)
      integer(int64) :: values, width
      ok = .false.
      if (size(bytes) < 4) return
      n = transfer(bytes(1:4), n)
      if (n < 1 .or. size(bytes) < 4 + n + 24) return
      allocate (character(len=n) :: item%name)
      item%name = transfer(bytes(5:4 + n), item%name)
      head = transfer(bytes(5 + n:4 + n + 24), head)
      item%kind = head(1)
      item%rank = head(2)
      item%lower = head(3:4)
      item%extent = head(5:6)
      if (any(item%extent < 0) .or. item%rank < 0 .or. item%rank > 2) return
      select case (item%kind)
      case (item_real)
         width = storage_size(0.0_dp)/8
      case (item_int, item_logical)
         width = storage_size(0)/8
      case (item_text)
         width = 1
      case default
         return
      end select
      values = int(item%extent(1), int64)*item%extent(2)
      if (item%kind == item_text) values = item%extent(1)
      if (size(bytes, kind=int64) - (4 + n + 24) /= values*width) return
      item%bytes = bytes(4 + n + 25:)
      ok = .true.
   end subroutine decode
end module mpm_state
