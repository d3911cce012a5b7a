!> Stable ordering of real keys (merge sort, O(n log n)): for case scheduling, medians and
!> merging shard tables, which may hold millions of entries.
module mpm_sort
   use mpm_kinds, only: dp
   implicit none
   private
   public :: sort_order, median, relative_spread

contains

   !> The permutation that puts `keys` in ascending order; equal keys keep their order.
   function sort_order(keys) result(order)
      real(dp), intent(in) :: keys(:)
      integer, allocatable :: order(:)
      integer, allocatable :: scratch(:)
      integer :: i
      order = [(i, i=1, size(keys))]
      allocate (scratch(size(keys)))
      call merge_sort(1, size(keys))
   contains
      recursive subroutine merge_sort(low, high)
         integer, intent(in) :: low, high
         integer :: middle, a, b, k
         if (high - low < 1) return
         middle = (low + high)/2
         call merge_sort(low, middle)
         call merge_sort(middle + 1, high)
         a = low
         b = middle + 1
         do k = low, high
            if (b > high) then
               scratch(k) = order(a)
               a = a + 1
            else if (a > middle) then
               scratch(k) = order(b)
               b = b + 1
            else if (keys(order(b)) < keys(order(a))) then
               scratch(k) = order(b)
               b = b + 1
            else
               scratch(k) = order(a)
               a = a + 1
            end if
         end do
         order(low:high) = scratch(low:high)
      end subroutine merge_sort
   end function sort_order

   !> Median of a non-empty array.
   real(dp) function median(values)
      real(dp), intent(in) :: values(:)
      integer, allocatable :: order(:)
      integer :: n
      n = size(values)
      order = sort_order(values)
      if (mod(n, 2) == 1) then
         median = values(order((n + 1)/2))
      else
         median = 0.5_dp*(values(order(n/2)) + values(order(n/2 + 1)))
      end if
   end function median

   !> Relative spread of a non-empty sample: its interquartile range over its median (quartiles
   !> by linear interpolation between order statistics, as numpy's default; 0 for one value).
   real(dp) function relative_spread(values)
      real(dp), intent(in) :: values(:)
      real(dp), allocatable :: sorted(:)
      sorted = values(sort_order(values))
      relative_spread = 0.0_dp
      if (size(values) > 1 .and. median(values) > 0.0_dp) &
         relative_spread = (quantile(0.75_dp) - quantile(0.25_dp))/median(values)
   contains
      real(dp) function quantile(q)
         real(dp), intent(in) :: q
         real(dp) :: position
         integer :: below
         position = q*(size(sorted) - 1) + 1
         below = min(int(position), size(sorted) - 1)
         quantile = sorted(below) + (position - below)*(sorted(below + 1) - sorted(below))
      end function quantile
   end function relative_spread
end module mpm_sort
