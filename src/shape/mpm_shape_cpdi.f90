!> CPDI in one dimension, the convected particle domain interpolation ([Sadeghirad 2011]; its second-order
!> form CPDI2 [Sadeghirad 2013]; references: docs/theory.md). Particle p's domain is the segment between
!> two corners x1 < x2, and neighbouring particles of a body share their corner, so that the domains tile
!> the body. Its weights are the hat's mean over the domain with the hat replaced by its linear interpolant
!> between the corners, and its gradients the exact mean of the hat's derivative over the domain:
!>   S_I = (N_I(x1) + N_I(x2))/2,   G_I = (N_I(x2) - N_I(x1))/(x2 - x1).
!> (In 1-D a domain is fixed by its two corners, so CPDI2, which tracks the corners instead of a
!> parallelogram deformed by F, is this.) The corners move with the grid velocity interpolated by the hat
!> at each corner (cpdi_move_corners); the particle's position is its domain's centre (cpdi_centres).
!> Only the nodes of the corners' cells carry weight; a domain whose corners lie in cells more than two apart
!> (possible from two cells' length, certain from three) needs more than the four nodes a particle touches
!> here (`stretched`: the run stops).
module mpm_shape_cpdi
   use mpm_kinds, only: dp
   implicit none
   private
   public :: cpdi_support, cpdi_corners, cpdi_shapes, cpdi_move_corners, cpdi_centres

   !> Nodes a particle touches: its domain's corners lie in cells at most two apart.
   integer, parameter :: cpdi_support = 4

contains

   !> The corners of the initial domains: particle p spans x0(p) -/+ volume0(p)/2 (its sub-cell), and
   !> each body (`body`, when the particles carry one; a contiguous range each, in order) gets one corner
   !> more than it has particles. corner_of(p) = the index (0-based) of p's left corner; its right one is
   !> corner_of(p) + 1. Corners beyond [lo, hi] (round-off at a fixed end of the grid) are put on it.
   pure subroutine cpdi_corners(x0, volume0, lo, hi, corners, corner_of, body)
      real(dp), intent(in), contiguous :: x0(:), volume0(:)
      real(dp), intent(in) :: lo, hi
      real(dp), allocatable, intent(out) :: corners(:)
      integer, allocatable, intent(out) :: corner_of(:)
      integer, intent(in), optional, contiguous :: body(:)
      integer :: p, c, n
      n = size(x0)
      allocate (corner_of(n))
      if (present(body)) then
         allocate (corners(0:n + body(n) - body(1)))
      else
         allocate (corners(0:n))
      end if
      c = 0
      do p = 1, n
         if (p == 1) then
            corners(c) = x0(p) - 0.5_dp*volume0(p)
         else if (present(body)) then
            if (body(p) /= body(p - 1)) then
               c = c + 1
               corners(c) = x0(p) - 0.5_dp*volume0(p)
            end if
         end if
         corner_of(p) = c
         c = c + 1
         corners(c) = x0(p) + 0.5_dp*volume0(p)
      end do
      corners = min(max(corners, lo), hi)
   end subroutine cpdi_corners

   !> Weights and gradients of every particle from its domain's corners on a grid of `cells` cells of size
   !> 1/inv_dx from `origin`: weight(p, k) and gradient(p, k) on nodes first(p) + k - 1, k = 1..4, where
   !> first(p) is the left node of the cell of its left corner, or, near the grid's right end, the node
   !> that makes the four columns end at the grid's last node (every node a column names exists: the
   !> operations read and write all four; the columns before the left corner's hold zeros).
   !> Needs at least 3 cells. A corner on a node belongs to the cell to its
   !> right, the grid's last node to the last cell. A particle with a corner outside the grid (NaN too)
   !> gets first = 0 and zero weights and gradients, `outside` = the first such particle (0 if none);
   !> `stretched` = the first particle whose corners lie in cells more than two apart (0 if none), which
   !> gets zero weights too.
   pure subroutine cpdi_shapes(origin, inv_dx, cells, corners, corner_of, first, weight, gradient, outside, &
                               stretched)
      real(dp), intent(in) :: origin, inv_dx
      integer, intent(in) :: cells
      real(dp), intent(in) :: corners(0:)
      integer, intent(in), contiguous :: corner_of(:)
      integer, intent(out), contiguous :: first(:)
      real(dp), intent(out), contiguous :: weight(:, :), gradient(:, :)
      integer, intent(out) :: outside, stretched
      integer :: p, left_cell, right_cell, j, k
      real(dp) :: s1, s2, xi1, xi2, inverse_length
      outside = 0
      stretched = 0
      do p = 1, size(first)
         s1 = (corners(corner_of(p)) - origin)*inv_dx
         s2 = (corners(corner_of(p) + 1) - origin)*inv_dx
         weight(p, :) = 0.0_dp
         gradient(p, :) = 0.0_dp
         first(p) = 0
         if (.not. (s1 >= 0.0_dp .and. s2 <= real(cells, dp))) then
            if (outside == 0) outside = p
            cycle
         end if
         left_cell = min(int(s1), cells - 1)
         right_cell = min(int(s2), cells - 1)
         if (right_cell - left_cell > 2) then
            if (stretched == 0) stretched = p
            cycle
         end if
         first(p) = min(left_cell, cells - 3)
         j = left_cell - first(p) + 1 ! (the support column of the left corner's left node)
         k = right_cell - first(p) + 1 ! (... and of the right corner's)
         xi1 = s1 - left_cell
         xi2 = s2 - right_cell
         inverse_length = inv_dx/(s2 - s1)
         weight(p, j) = 0.5_dp*(1.0_dp - xi1)
         weight(p, j + 1) = 0.5_dp*xi1
         gradient(p, j) = -(1.0_dp - xi1)*inverse_length
         gradient(p, j + 1) = -xi1*inverse_length
         weight(p, k) = weight(p, k) + 0.5_dp*(1.0_dp - xi2)
         weight(p, k + 1) = weight(p, k + 1) + 0.5_dp*xi2
         gradient(p, k) = gradient(p, k) + (1.0_dp - xi2)*inverse_length
         gradient(p, k + 1) = gradient(p, k + 1) + xi2*inverse_length
      end do
   end subroutine cpdi_shapes

   !> Each corner moved by dt times the grid velocity the hat interpolates there,
   !> x_c += dt sum_I N_I(x_c) v_I (a corner on a node takes that node's velocity; a corner outside the
   !> grid does not move: the particle's shapes have stopped the run already).
   pure subroutine cpdi_move_corners(origin, inv_dx, cells, velocity, dt, corners)
      real(dp), intent(in) :: origin, inv_dx, dt
      integer, intent(in) :: cells
      real(dp), intent(in) :: velocity(0:)
      real(dp), intent(inout) :: corners(0:)
      integer :: c, e
      real(dp) :: s, xi
      do c = 0, ubound(corners, 1)
         s = (corners(c) - origin)*inv_dx
         if (.not. (s >= 0.0_dp .and. s <= real(cells, dp))) cycle
         e = min(int(s), cells - 1)
         xi = s - e
         corners(c) = corners(c) + dt*((1.0_dp - xi)*velocity(e) + xi*velocity(e + 1))
      end do
   end subroutine cpdi_move_corners

   !> Each particle's position: its domain's centre.
   pure subroutine cpdi_centres(corners, corner_of, x)
      real(dp), intent(in) :: corners(0:)
      integer, intent(in), contiguous :: corner_of(:)
      real(dp), intent(inout), contiguous :: x(:)
      integer :: p
      do p = 1, size(x)
         x(p) = 0.5_dp*(corners(corner_of(p)) + corners(corner_of(p) + 1))
      end do
   end subroutine cpdi_centres
end module mpm_shape_cpdi
