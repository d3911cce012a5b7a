!> The mirror ghosts at a fixed end (mpm_operations' mirror_fold: why the image of the body is its mirror):
!> the fold of one nodal field, even (a mass) or odd (a momentum, a force), at x = 0 (grid%mirror, node
!> grid%ghost) and at a fixed right end (grid%mirror_right).
module mpm_mirror
   use mpm_kinds, only: dp
   use mpm_grid, only: grid_t
   implicit none
   private
   public :: mirror_even, mirror_odd

contains

   !> The fold of a nodal field whose image is its mirror (a mass): at a mirrored fixed end node c + j gets
   !> node c - j's share added and node c - j the sum. At a fixed right end x = L (grid%mirror_right = r, the
   !> manufactured scene's) margin node r + j is node r - j reflected, as at x = 0 (the solution is odd about
   !> a fixed end there too). Without it the margin nodes beyond a fixed end moved freely, and the wide
   !> shapes' particles next to it followed them (first order, and through the wall at large strain).
   subroutine mirror_even(grid, field)
      type(grid_t), intent(in) :: grid
      real(dp), intent(inout), contiguous :: field(0:)
      call mirror_field(grid, field, 1.0_dp)
   end subroutine mirror_even

   !> The fold of a nodal field whose image is its negative mirror (a momentum, a force): as mirror_even,
   !> with the image's share subtracted and the ghost node holding the negative of its partner.
   subroutine mirror_odd(grid, field)
      type(grid_t), intent(in) :: grid
      real(dp), intent(inout), contiguous :: field(0:)
      call mirror_field(grid, field, -1.0_dp)
   end subroutine mirror_odd

   !> The fold with the image's sign `parity` (1 or -1: the products are exact, so the sums are those of the
   !> fold written with + and -).
   subroutine mirror_field(grid, field, parity)
      type(grid_t), intent(in) :: grid
      real(dp), intent(inout), contiguous :: field(0:)
      real(dp), intent(in) :: parity
      integer :: j, c, r
      r = grid%mirror_right
      if (r >= 0) then
         do j = 1, grid%ghost
            field(r - j) = field(r - j) + parity*field(r + j)
            field(r + j) = parity*field(r - j)
         end do
      end if
      if (.not. grid%mirror) return
      c = grid%ghost
      do j = 1, c
         field(c + j) = field(c + j) + parity*field(c - j)
         field(c - j) = parity*field(c + j)
      end do
   end subroutine mirror_field
end module mpm_mirror
