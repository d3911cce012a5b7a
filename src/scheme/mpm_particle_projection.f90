!> The particle projection of XPIC and FMPM ([Hammerquist & Nairn 2017], [Nairn & Hammerquist 2021];
!> references: docs/theory.md): on a grid velocity w,
!>   A w = M_L^-1 S^T diag(m_p) S w,   (A w)_I = sum_p N_Ip m_p (sum_J N_Jp w_J) / m_I,
!> a gather of w to the particles, a P2G of m_p times it (reflected at a mirrored fixed end as a momentum is,
!> mpm_mirror's mirror_odd), divided by the lumped mass (empty nodes 0) and the fixed nodes held at 0
!> after each application. Both methods use the series sum_{r<n} (I - A)^r w: XPIC(m)'s v* on v^n is it with
!> n = m (its binomial sum of powers of A is the same polynomial), FMPM(k)'s v_k(q) with n = k on M_L^-1 q.
module mpm_particle_projection
   use mpm_kinds, only: dp
   use mpm_grid, only: grid_t, zero_fixed
   use mpm_shape, only: shape_cache_t
   use mpm_mirror, only: mirror_odd
   implicit none
   private
   public :: projection_series, series_term, grid_scratch, velocity_of_momentum

contains

   !> field <- sum_{r<order} (I - A)^r field, in place (order >= 1; 1 leaves it alone), with the weights of
   !> the step (support, first, weight: the shape cache's); term, projected (grid) and carried (particles)
   !> are scratch.
   subroutine projection_series(support, first, weight, mass_of, grid, order, field, term, projected, carried)
      integer, intent(in) :: support
      integer, intent(in), contiguous :: first(:)
      real(dp), intent(in), contiguous :: weight(:, :), mass_of(:)
      type(grid_t), intent(in) :: grid
      integer, intent(in) :: order
      real(dp), intent(inout), contiguous :: field(0:)
      real(dp), intent(out), contiguous :: term(0:), projected(0:), carried(:)
      integer :: r
      if (order <= 1) return
      term = field
      do r = 1, order - 1
         call gather_scatter(support, first, weight, mass_of, term, projected, carried)
         call series_term(grid, field, term, projected)
      end do
   end subroutine projection_series

   !> One term of the series: from projected = S^T diag(m_p) S term (a P2G of the particles' m_p times term
   !> gathered), term <- (I - A) term and field <- field + term. The fused kernels' particles gather and
   !> scatter by their own layout (mpm_fused_projection) and share this.
   subroutine series_term(grid, field, term, projected)
      type(grid_t), intent(in) :: grid
      real(dp), intent(inout), contiguous :: field(0:), term(0:), projected(0:)
      call mirror_odd(grid, projected)
      call velocity_of_momentum(grid, projected)
      term = term - projected
      field = field + term
   end subroutine series_term

   !> out_I = sum_p N_Ip m_p (sum_J N_Jp w_J); `carried` is scratch (the particles' m_p sum_J N_Jp w_J).
   subroutine gather_scatter(support, first, weight, mass_of, w, out, carried)
      integer, intent(in) :: support
      integer, intent(in), contiguous :: first(:)
      real(dp), intent(in), contiguous :: weight(:, :), mass_of(:), w(0:)
      real(dp), intent(out), contiguous :: out(0:), carried(:)
      integer :: p, k
      carried = 0.0_dp
      do k = 1, support
         do p = 1, size(first)
            carried(p) = carried(p) + weight(p, k)*w(first(p) + k - 1)
         end do
      end do
      carried = mass_of*carried
      out = 0.0_dp
      do p = 1, size(first)
         do k = 1, support
            out(first(p) + k - 1) = out(first(p) + k - 1) + weight(p, k)*carried(p)
         end do
      end do
   end subroutine gather_scatter

   !> A grid momentum into its velocity, in place: field / m_I (0 on empty nodes), the fixed nodes held at 0.
   subroutine velocity_of_momentum(grid, field)
      type(grid_t), intent(in) :: grid
      real(dp), intent(inout), contiguous :: field(0:)
      where (grid%mass > grid%empty_mass)
         field = field/grid%mass
      elsewhere
         field = 0.0_dp
      end where
      call zero_fixed(grid%fixed, field)
   end subroutine velocity_of_momentum

   !> The transfers' scratch, allocated on first use: cache%grid_work (3 columns on the grid's nodes) and
   !> cache%work (one value per particle).
   subroutine grid_scratch(cache, grid)
      type(shape_cache_t), intent(inout) :: cache
      type(grid_t), intent(in) :: grid
      if (.not. allocated(cache%grid_work)) allocate (cache%grid_work(0:grid%elements, 3))
      if (.not. allocated(cache%work)) allocate (cache%work(size(cache%first), 3))
   end subroutine grid_scratch
end module mpm_particle_projection
