!> Linear (2-node, "hat") shape functions of the uniform 1-D grid.
!> For a particle at x in element e (1-based, spanning nodes e-1 and e) with local coordinate
!> xi = (x - origin)/dx - (e-1) in [0, 1]: N_left = 1 - xi, N_right = xi, dN_left/dx = -1/dx,
!> dN_right/dx = +1/dx. The gradient jumps where a particle crosses a node ("grid-crossing error").
module mpm_shape_linear
   use mpm_kinds, only: dp, i8
   use mpm_shape_range, only: infinity_bits
   implicit none
   private
   public :: linear_support, linear_shapes, locate, shape_left, shape_right

   !> Nodes a particle touches.
   integer, parameter :: linear_support = 2

contains

   !> Weights and gradients of every particle at positions `x` on a grid of `cells` cells of size
   !> 1/inv_dx from `origin`: first(p) = its element's left node (0-based node index), weight(p, :) and
   !> gradient(p, :) on nodes first(p) and first(p) + 1. A particle outside the domain (NaN too) gets
   !> first = 0 and zero weights and gradients (it adds nothing, and the loops need no test);
   !> `outside` is the first such particle (0 if none). The far end of the domain belongs to the last
   !> element (xi = 1). The loop has no branch and no floating-point comparison (inside_range), so that
   !> it vectorises.
   pure subroutine linear_shapes(origin, inv_dx, cells, x, first, weight, gradient, outside)
      real(dp), intent(in) :: origin, inv_dx
      integer, intent(in) :: cells
      real(dp), intent(in), contiguous :: x(:)
      integer, intent(out), contiguous :: first(:)
      real(dp), intent(out), contiguous :: weight(:, :), gradient(:, :)
      integer, intent(out) :: outside
      integer :: p, e, flag
      integer(i8) :: below, above
      real(dp) :: xi, s, inside
      outside = huge(1)
      do p = 1, size(x)
         s = (x(p) - origin)*inv_dx
         below = transfer(s, 0_i8)  ! flag = inside_range(s, 0.0_dp, real(cells, dp)), written out
         above = transfer(real(cells, dp) - s, 0_i8)
         flag = int(1_i8 - ishft(ior(ior(below, above), infinity_bits - below), -63))
         inside = real(flag, dp)
         outside = min(outside, p + (huge(1) - p)*flag)
         s = merge(s, 0.0_dp, flag == 1)
         e = min(int(s), cells - 1)
         xi = s - e
         first(p) = e
         weight(p, 1) = (1.0_dp - xi)*inside
         weight(p, 2) = xi*inside
         gradient(p, 1) = -inv_dx*inside
         gradient(p, 2) = inv_dx*inside
      end do
      if (outside == huge(1)) outside = 0
   end subroutine linear_shapes

   !> Element `cell` (1..elements) and local coordinate `xi` of position `x` (from the grid's origin).
   !> A position outside [0, elements*dx] gives cell = 0 (left of the grid, NaN too) or elements + 1
   !> (right). The far end x = elements*dx itself belongs to the last element (xi = 1).
   elemental subroutine locate(x, inv_dx, elements, cell, xi)
      real(dp), intent(in) :: x, inv_dx
      integer, intent(in) :: elements
      integer, intent(out) :: cell
      real(dp), intent(out) :: xi
      real(dp) :: s
      s = x*inv_dx
      if (s >= 0.0_dp .and. s < real(elements, dp)) then
         cell = int(s) + 1
         xi = s - (cell - 1)
      else if (s == real(elements, dp)) then
         cell = elements
         xi = 1.0_dp
      else if (s > real(elements, dp)) then
         cell = elements + 1
         xi = 0.0_dp
      else
         cell = 0
         xi = 0.0_dp
      end if
   end subroutine locate

   !> N of the element's left node at local coordinate xi.
   elemental real(dp) function shape_left(xi)
      real(dp), intent(in) :: xi
      shape_left = 1.0_dp - xi
   end function shape_left

   !> N of the element's right node at local coordinate xi.
   elemental real(dp) function shape_right(xi)
      real(dp), intent(in) :: xi
      shape_right = xi
   end function shape_right
end module mpm_shape_linear
