!> Generalized Interpolation Material Point shape functions ([Bardenhagen & Kober 2004]; references:
!> docs/theory.md) on the uniform 1-D grid.
!> A particle is a box [x_p - l_p, x_p + l_p] of uniform characteristic function chi_p; its weight
!> on node I is the box average of the hat function N_I (their eq. 36 with chi_p = 1 on the box):
!>    S_I(x_p) = 1/(2 l_p) int_{x_p - l_p}^{x_p + l_p} N_I(x) dx,
!>    dS_I/dx_p = (N_I(x_p + l_p) - N_I(x_p - l_p)) / (2 l_p).
!> With l = l_p/dx <= 1/2 the box spans at most one node: in grid units s = (x_p - origin)/dx, let
!> i = floor(s - l) (the cell of the box's left end), m = i + 1 and d = s - m in [l - 1, l). The
!> box is split by node m into a left part, the fraction r1 = 1 - r2 of it, in cell i, and a right
!> part, the fraction r2 = max(0, d + l)/(2 l), in cell i + 1. In each cell the hats are linear, so
!> each part gives the hat values at its centroid: t1 = 1 + (min(d - l, 0) + min(d + l, 0))/2 (local
!> coordinate in cell i) and t2 = (max(d - l, 0) + max(d + l, 0))/2 (in cell i + 1; the max(d - l, 0)
!> only matters at the far end of the grid, where i is held at cells - 2 and the box lies in cell i + 1):
!>    S_i = r1 (1 - t1),  S_m = r1 t1 + r2 (1 - t2),  S_{m+1} = r2 t2,
!>    dS/dx = [-r1, r1 - r2, r2] / dx   (the formula above: N_i(b) - N_i(a) = -2 l r1, ...).
!> Partition of unity holds by construction (r1 + r2 = 1), the box centroid is reproduced, and no
!> difference of nearly equal numbers is divided by l_p (round-off stays at ulps for short boxes);
!> branch-free, so that the loop vectorises. uGIMP keeps l_p = l_p0 = dx/(2 ppc); cpGIMP (contiguous
!> particle GIMP, [Bardenhagen & Kober 2004], sec. 3.3) stretches it with the particle, l_p = l_p0 J_p
!> (exact in 1-D: the particle's length is its volume per unit area). The caller passes the half-lengths.
!> l_p is capped at dx/2 so that a box spans at most two cells (3 nodes; reached only by ppc = 1
!> stretched, or ppc = 2 at J = 2), and floored at 1e-9 dx (a collapsed particle, J -> 0, trips the
!> J guard anyway).
module mpm_shape_gimp
   use mpm_kinds, only: dp, i8
   use mpm_shape_range, only: infinity_bits
   implicit none
   private
   public :: gimp_support, gimp_shapes, gimp_checksum_compiled

   !> The checksum of mpm_gimp_box.inc, which this module includes (fpm does not notice a change of an
   !> included file, fpm issue #358: see kernel_source_checksum in mpm_transfer); test_shape checks it.
   integer(i8), parameter :: gimp_source_checksum = 295088833_i8

   !> Nodes a particle touches (a box of at most one cell spans at most two cells).
   integer, parameter :: gimp_support = 3

contains

   !> gimp_source_checksum as compiled into this module (see kernel_checksum_compiled in mpm_transfer).
   integer(i8) function gimp_checksum_compiled()
      gimp_checksum_compiled = gimp_source_checksum
   end function gimp_checksum_compiled

   !> Weights and gradients of every particle at positions `x` with box half-lengths `half_length`
   !> on a grid of `cells` cells of size 1/inv_dx from `origin`; node first(p) + k - 1 gets
   !> weight(p, k), gradient(p, k). A particle whose box is not inside the domain (NaN too) gets
   !> first = 0 and zero weights; `outside` = the first such particle (0 if none).
   pure subroutine gimp_shapes(origin, inv_dx, cells, x, half_length, first, weight, gradient, outside)
      real(dp), intent(in) :: origin, inv_dx
      integer, intent(in) :: cells
      real(dp), intent(in), contiguous :: x(:), half_length(:)
      integer, intent(out), contiguous :: first(:)
      real(dp), intent(out), contiguous :: weight(:, :), gradient(:, :)
      integer, intent(out) :: outside
      integer :: p, i, flag
      real(dp) :: s, l, inside, r1, r2, t1, t2
      outside = huge(1)
      do p = 1, size(x)
         s = (x(p) - origin)*inv_dx
         l = min(max(half_length(p)*inv_dx, 1.0e-9_dp), 0.5_dp)
         call gimp_box(s, l, cells, i, r1, r2, t1, t2, flag)
         inside = real(flag, dp)
         outside = min(outside, p + (huge(1) - p)*flag)
         first(p) = i
         weight(p, 1) = r1*(1.0_dp - t1)*inside
         weight(p, 2) = (r1*t1 + r2*(1.0_dp - t2))*inside
         weight(p, 3) = r2*t2*inside
         gradient(p, 1) = -r1*inv_dx*inside
         gradient(p, 2) = (r1 - r2)*inv_dx*inside
         gradient(p, 3) = r2*inv_dx*inside
      end do
      if (outside == huge(1)) outside = 0
   end subroutine gimp_shapes

   include 'mpm_gimp_box.inc'
end module mpm_shape_gimp
