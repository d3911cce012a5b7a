!> Generalized Interpolation Material Point shape functions (Bardenhagen and Kober 2004, "The
!> generalized interpolation material point method", CMES 5(6):477-495) on the uniform 1-D grid.
!> A particle is a box [x_p - l_p, x_p + l_p] of uniform characteristic function chi_p; its weight
!> on node I is the box average of the hat function N_I (their eq. 36 with chi_p = 1 on the box):
!>    S_I(x_p) = 1/(2 l_p) int_{x_p - l_p}^{x_p + l_p} N_I(x) dx,
!>    dS_I/dx_p = (N_I(x_p + l_p) - N_I(x_p - l_p)) / (2 l_p).
!> With c = (x_p - x_I)/dx and l = l_p/dx, write the hat as ramps, N(c) = r(c+1) - 2 r(c) + r(c-1),
!> r(u) = max(u, 0): the box average of a ramp differs from its value at the centre only where the
!> box holds its kink, by q(u) = max(0, l - |u|)^2 / (4 l). So
!>    S_I = N(c) + q(c+1) - 2 q(c) + q(c-1),
!>    dS_I/dx_p = (N'(c) + q'(c+1) - 2 q'(c) + q'(c-1)) / dx,  q'(u) = -sign(u) max(0, l - |u|) / (2 l):
!> exact for any l (the paper's piecewise formulas for l_p <= dx/2 follow), free of the cancellation
!> of a difference of antiderivatives over a short box (round-off stays at ulps for any l_p), and
!> branch-free so that the loop vectorises. uGIMP keeps l_p = l_p0 = dx/(2 ppc); cpGIMP (contiguous
!> particle GIMP, Bardenhagen and Kober 2004, sec. 3.3) stretches it with the particle, l_p = l_p0 J_p
!> (exact in 1-D: the particle's length is its volume per unit area). The caller passes the half-lengths.
!> l_p is capped at dx/2 so that a box spans at most two cells (3 nodes; reached only by ppc = 1
!> stretched, or ppc = 2 at J = 2), and floored at 1e-9 dx (a collapsed particle, J -> 0, trips the
!> J guard anyway).
module mpm_shape_gimp
   use mpm_kinds, only: dp
   implicit none
   private
   public :: gimp_support, gimp_shapes

   !> Nodes a particle touches (a box of at most one cell spans at most two cells).
   integer, parameter :: gimp_support = 3

contains

   !> Weights and gradients of every particle at positions `x` with box half-lengths `half_length`
   !> on a grid of `cells` cells of size 1/inv_dx from `origin`; node first(p) + k - 1 gets
   !> weight(p, k), gradient(p, k). A particle whose box is not inside the domain (NaN too) gets
   !> first = 0 and zero weights; `outside` = the first such particle (0 if none).
   pure subroutine gimp_shapes(origin, inv_dx, cells, x, half_length, first, weight, gradient, outside)
      real(dp), intent(in) :: origin, inv_dx
      integer, intent(in) :: cells
      real(dp), intent(in) :: x(:), half_length(:)
      integer, intent(out) :: first(:)
      real(dp), intent(out) :: weight(:, :), gradient(:, :)
      integer, intent(out) :: outside
      integer :: p, k, i
      real(dp) :: s, l, inside, c, quarter
      do p = 1, size(x)
         s = (x(p) - origin)*inv_dx
         l = min(max(half_length(p)*inv_dx, 1.0e-9_dp), 0.5_dp)
         inside = merge(1.0_dp, 0.0_dp, s - l >= 0.0_dp .and. s + l <= real(cells, dp))
         s = merge(s, 0.5_dp*cells, inside > 0.0_dp)
         i = min(int(s - l), cells - 2)
         first(p) = i
         quarter = 0.25_dp/l
         do k = 1, gimp_support
            c = s - (i + k - 1)
            weight(p, k) = (max(0.0_dp, 1.0_dp - abs(c)) + quarter*(max(0.0_dp, l - abs(c + 1.0_dp))**2 &
                            - 2.0_dp*max(0.0_dp, l - abs(c))**2 + max(0.0_dp, l - abs(c - 1.0_dp))**2))*inside
            gradient(p, k) = (merge(-sign(1.0_dp, c), 0.0_dp, abs(c) < 1.0_dp) &
                              - 2.0_dp*quarter*(sign(max(0.0_dp, l - abs(c + 1.0_dp)), c + 1.0_dp) &
                                                - 2.0_dp*sign(max(0.0_dp, l - abs(c)), c) &
                                                + sign(max(0.0_dp, l - abs(c - 1.0_dp)), c - 1.0_dp)))*inv_dx*inside
         end do
      end do
      outside = 0
      do p = 1, size(x)
         s = (x(p) - origin)*inv_dx
         l = min(max(half_length(p)*inv_dx, 1.0e-9_dp), 0.5_dp)
         if (.not. (s - l >= 0.0_dp .and. s + l <= real(cells, dp))) then
            outside = p
            exit
         end if
      end do
   end subroutine gimp_shapes

end module mpm_shape_gimp
