!> Linear (2-node, "hat") shape functions of the uniform 1-D grid.
!> For a particle at x in element e (1-based, spanning nodes e-1 and e) with local coordinate
!> xi = x/dx - (e-1) in [0, 1]: N_left = 1 - xi, N_right = xi, dN_left/dx = -1/dx, dN_right/dx = +1/dx.
module mpm_shape
   use mpm_kinds, only: dp
   implicit none
   private
   public :: locate, shape_left, shape_right

contains

   !> Element `cell` (1..elements) and local coordinate `xi` of position `x`.
   !> A position outside [0, elements*dx] gives cell = 0 (left of the grid) or elements + 1 (right).
   !> The far end x = length itself belongs to the last element (xi = 1).
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
      else if (s < 0.0_dp) then
         cell = 0
         xi = 0.0_dp
      else
         cell = elements + 1
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
end module mpm_shape
