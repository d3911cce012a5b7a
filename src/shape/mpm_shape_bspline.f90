!> Quadratic and cubic B-spline shape functions on the uniform 1-D grid, centred on the nodes
!> ([Steffen 2008], eqs. for S_2 and S_3; the uniform B-splines of [de Boor]; references:
!> docs/theory.md):
!>   quadratic, r = |x - x_I|/dx:  3/4 - r^2 (r <= 1/2),  (3/2 - r)^2/2 (1/2 <= r <= 3/2), 0 beyond;
!>   cubic:                        2/3 - r^2 + r^3/2 (r <= 1),  (2 - r)^3/6 (1 <= r <= 2), 0 beyond.
!> Both are C^1 (quadratic) or C^2 (cubic), so the gradient no longer jumps when a particle crosses
!> a node. Written per local coordinate t in [0, 1) of the particle in its "knot span", one
!> polynomial per node of the support, no branch (vectorises):
!>   quadratic: first = nint-below(s) - 1, t = s + 1/2 - (first + 1):
!>     N = [(1-t)^2/2, 1/2 + t - t^2, t^2/2],  dN/dt = [t - 1, 1 - 2t, t]
!>   cubic: first = floor(s) - 1, t = s - (first + 1):
!>     N = [(1-t)^3/6, (3t^3 - 6t^2 + 4)/6, (-3t^3 + 3t^2 + 3t + 1)/6, t^3/6],
!>     dN/dt = [-(1-t)^2/2, 3t^2/2 - 2t, -3t^2/2 + t + 1/2, t^2/2].
!> Boundaries are the grid's business (mpm_grid: a ghost cell beyond a fixed end, mirrored), so
!> these are the plain uniform B-splines wherever the support lies inside the grid; a particle whose
!> support leaves the grid is flagged.
module mpm_shape_bspline
   use mpm_kinds, only: dp, i8
   use mpm_shape_range, only: infinity_bits
   implicit none
   private
   public :: bspline2_support, bspline3_support, bspline2_shapes, bspline3_shapes, bspline_checksum_compiled

   !> The checksum of mpm_bspline_span.inc, which this module includes (fpm does not notice a change of
   !> an included file, fpm issue #358: see kernel_source_checksum in mpm_transfer); test_shape checks it.
   integer(i8), parameter :: bspline_source_checksum = 209635134_i8

   integer, parameter :: bspline2_support = 3, bspline3_support = 4

contains

   !> bspline_source_checksum as compiled into this module (see kernel_checksum_compiled in mpm_transfer).
   integer(i8) function bspline_checksum_compiled()
      bspline_checksum_compiled = bspline_source_checksum
   end function bspline_checksum_compiled

   !> Quadratic B-spline weights and gradients of every particle (conventions of gimp_shapes: node
   !> first(p) + k - 1; a particle whose support is not inside the grid gets first = 0 and zero weights).
   pure subroutine bspline2_shapes(origin, inv_dx, cells, x, first, weight, gradient, outside)
      real(dp), intent(in) :: origin, inv_dx
      integer, intent(in) :: cells
      real(dp), intent(in), contiguous :: x(:)
      integer, intent(out), contiguous :: first(:)
      real(dp), intent(out), contiguous :: weight(:, :), gradient(:, :)
      integer, intent(out) :: outside
      integer :: p, i, flag
      real(dp) :: t, inside
      outside = huge(1)
      do p = 1, size(x)
         call bspline2_span((x(p) - origin)*inv_dx, cells, i, t, flag)
         inside = real(flag, dp)
         outside = min(outside, p + (huge(1) - p)*flag)
         first(p) = i
         weight(p, 1) = 0.5_dp*(1.0_dp - t)**2*inside
         weight(p, 2) = (0.5_dp + t - t*t)*inside
         weight(p, 3) = 0.5_dp*t*t*inside
         gradient(p, 1) = (t - 1.0_dp)*inv_dx*inside
         gradient(p, 2) = (1.0_dp - 2.0_dp*t)*inv_dx*inside
         gradient(p, 3) = t*inv_dx*inside
      end do
      if (outside == huge(1)) outside = 0
   end subroutine bspline2_shapes

   !> Cubic B-spline weights and gradients of every particle (conventions as bspline2_shapes). Two
   !> loops, weights then gradients, each locating the particle again: in one loop the ten arrays made
   !> gfortran give up vectorising (too many run-time alias checks), which cost 3x.
   pure subroutine bspline3_shapes(origin, inv_dx, cells, x, first, weight, gradient, outside)
      real(dp), intent(in) :: origin, inv_dx
      integer, intent(in) :: cells
      real(dp), intent(in), contiguous :: x(:)
      integer, intent(out), contiguous :: first(:)
      real(dp), intent(out), contiguous :: weight(:, :), gradient(:, :)
      integer, intent(out) :: outside
      integer :: p, i, flag
      real(dp) :: t, u, inside
      real(dp), parameter :: sixth = 1.0_dp/6.0_dp
      outside = huge(1)
      do p = 1, size(x)
         call bspline3_locate(x(p), origin, inv_dx, cells, i, t, flag)
         inside = real(flag, dp)
         outside = min(outside, p + (huge(1) - p)*flag)
         u = 1.0_dp - t
         first(p) = i
         weight(p, 1) = sixth*u*u*u*inside
         weight(p, 2) = sixth*(3.0_dp*t*t*t - 6.0_dp*t*t + 4.0_dp)*inside
         weight(p, 3) = sixth*(-3.0_dp*t*t*t + 3.0_dp*t*t + 3.0_dp*t + 1.0_dp)*inside
         weight(p, 4) = sixth*t*t*t*inside
      end do
      do p = 1, size(x)
         call bspline3_locate(x(p), origin, inv_dx, cells, i, t, flag)
         inside = real(flag, dp)
         u = 1.0_dp - t
         gradient(p, 1) = -0.5_dp*u*u*inv_dx*inside
         gradient(p, 2) = (1.5_dp*t*t - 2.0_dp*t)*inv_dx*inside
         gradient(p, 3) = (-1.5_dp*t*t + t + 0.5_dp)*inv_dx*inside
         gradient(p, 4) = 0.5_dp*t*t*inv_dx*inside
      end do
      if (outside == huge(1)) outside = 0
   end subroutine bspline3_shapes


   include 'mpm_bspline_span.inc'
end module mpm_shape_bspline
