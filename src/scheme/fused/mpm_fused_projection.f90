!> XPIC's and FMPM's particle projection A (mpm_particle_projection; [Hammerquist & Nairn 2017], [Nairn &
!> Hammerquist 2021], references: docs/theory.md) on the fused kernels' particles: the hat, one particle
!> mass, each particle's cell kept by the passes (particles%cell, 0 outside the grid). A w needs one more
!> pass over the particles per application: each gathers w by its cell and local coordinate, and a run of
!> particles in one element sums its shares (m N_I w_p) in registers and adds them to the element's two
!> nodes once, in particle order, so that the result does not depend on the thread count. The series
!> (sum_{r<n} (I - A)^r w) is the generic path's (series_term), on grid scratch kept by the caller.
module mpm_fused_projection
   use mpm_kinds, only: dp
   use mpm_grid, only: grid_t
   use mpm_particles, only: particles_t
   use mpm_lanes, only: block_size
   use mpm_particle_projection, only: series_term
   implicit none
   private
   public :: fused_projection_series

contains

   !> field <- sum_{r<order} (I - A)^r field, in place (order >= 1; 1 leaves it alone), with the particles
   !> where they are (the step's start: their cells are current); term and projected are grid scratch.
   subroutine fused_projection_series(particles, grid, order, field, term, projected)
      type(particles_t), intent(in) :: particles
      type(grid_t), intent(in) :: grid
      integer, intent(in) :: order
      real(dp), intent(inout), contiguous :: field(0:)
      real(dp), intent(out), contiguous :: term(0:), projected(0:)
      integer :: r
      if (order <= 1) return
      term = field
      do r = 1, order - 1
         call gather_scatter(particles%count, particles%x, particles%cell, particles%mass, grid%origin, grid%inv_dx, &
                             term, projected)
         call series_term(grid, field, term, projected)
      end do
   end subroutine fused_projection_series

   !> out_I = sum_p N_Ip m (sum_J N_Jp w_J), the hat's weights of each particle's cell: per block, the
   !> particles' shares in a loop without a branch, then the runs of one element summed in particle order.
   !> A particle outside the grid (cell 0: the run stops after this step) adds nothing.
   subroutine gather_scatter(n, x, cell, mass, origin, inv_dx, w, out)
      integer, intent(in) :: n
      real(dp), intent(in), contiguous :: x(:)
      integer, intent(in), contiguous :: cell(:)
      real(dp), intent(in) :: mass, origin, inv_dx
      real(dp), intent(in), contiguous :: w(0:)
      real(dp), intent(out), contiguous :: out(0:)
      integer :: b0, nb, i, p, e, cur, eb(block_size)
      real(dp) :: xi, c, inside, left, right, lb(block_size), rb(block_size)
      out = 0.0_dp
      cur = 0
      left = 0.0_dp
      right = 0.0_dp
      do b0 = 1, n, block_size
         nb = min(block_size, n - b0 + 1)
         do i = 1, nb
            p = b0 + i - 1
            e = max(cell(p), 1)
            inside = real(min(cell(p), 1), dp)
            eb(i) = e
            xi = (x(p) - origin)*inv_dx - (e - 1)
            c = inside*mass*((1.0_dp - xi)*w(e - 1) + xi*w(e))
            lb(i) = (1.0_dp - xi)*c
            rb(i) = xi*c
         end do
         do i = 1, nb
            if (eb(i) /= cur) then
               if (cur /= 0) then
                  out(cur - 1) = out(cur - 1) + left
                  out(cur) = out(cur) + right
               end if
               cur = eb(i)
               left = 0.0_dp
               right = 0.0_dp
            end if
            left = left + lb(i)
            right = right + rb(i)
         end do
      end do
      if (cur /= 0) then
         out(cur - 1) = out(cur - 1) + left
         out(cur) = out(cur) + right
      end if
   end subroutine gather_scatter
end module mpm_fused_projection
