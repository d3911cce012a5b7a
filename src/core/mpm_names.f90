!> Families of named ids (update schemes, integrators, shapes, transfers, laws, run statuses), each
!> written once as the list of its names: "a, b, c" names the ids first, first + 1, first + 2. The
!> list is also the family's known-list text (messages, the registry's allowed words), so that a
!> name, its id and the list of known names cannot disagree.
module mpm_names
   implicit none
   private
   public :: name_id, id_name

contains

   !> The id of `name` (trailing blanks ignored) in the comma-separated `names`, whose first name has
   !> id `first` (1 when absent); first - 1 when `name` is not in the list. (No allocation: runs and
   !> sweeps look their ids up once per case.)
   pure integer function name_id(name, names, first)
      character(len=*), intent(in) :: name, names
      integer, intent(in), optional :: first
      integer :: k, start, finish, next, n
      n = len_trim(name)
      k = 0
      start = 1
      do while (start <= len(names))
         call next_word(names, start, finish, next)
         k = k + 1
         if (finish - start + 1 == n .and. n > 0) then
            if (names(start:finish) == name(1:n)) exit
         end if
         start = next
      end do
      if (start > len(names)) k = 0
      name_id = k + base(first) - 1
   end function name_id

   !> The name of id `id` in the comma-separated `names` (ids from `first`, 1 when absent); 'unknown'
   !> for an id outside the list.
   pure function id_name(id, names, first) result(name)
      integer, intent(in) :: id
      character(len=*), intent(in) :: names
      integer, intent(in), optional :: first
      character(len=:), allocatable :: name
      integer :: k, start, finish, next
      name = 'unknown'
      k = base(first)
      start = 1
      do while (start <= len(names))
         call next_word(names, start, finish, next)
         if (k == id) then
            name = names(start:finish)
            return
         end if
         k = k + 1
         start = next
      end do
   end function id_name

   pure integer function base(first)
      integer, intent(in), optional :: first
      base = 1
      if (present(first)) base = first
   end function base

   !> The word of `names` from `start` (moved past leading blanks) to `finish` (its last character
   !> that is not a blank before the next comma or the end); `next` just after that comma (beyond
   !> the text after the last word).
   pure subroutine next_word(names, start, finish, next)
      character(len=*), intent(in) :: names
      integer, intent(inout) :: start
      integer, intent(out) :: finish, next
      integer :: comma
      do while (start < len(names))
         if (names(start:start) /= ' ') exit
         start = start + 1
      end do
      comma = index(names(start:), ',')
      if (comma == 0) then
         finish = len_trim(names)
         next = len(names) + 1
      else
         finish = start + comma - 2
         next = start + comma
      end if
      do while (finish > start)
         if (names(finish:finish) /= ' ') exit
         finish = finish - 1
      end do
   end subroutine next_word
end module mpm_names
