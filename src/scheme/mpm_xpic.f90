!> XPIC(m), the extended particle-in-cell update ([Hammerquist & Nairn 2017]; references: docs/theory.md):
!> from the step's P2G velocity v^n = p/m (before the force update),
!>   v* = sum_{k=1..m} (-1)^(k+1) C(m, k) A^(k-1) v^n = sum_{r<m} (I - A)^r v^n
!> (A the particle projection, mpm_particle_projection: the two sums are one polynomial in A, and the second
!> is the one evaluated, without the binomial's cancellation), and in G2P
!>   v_p = sum_I N_Ip (v*_I + dt a_I),   x_p += dt sum_I N_Ip v^L_I,
!> positions and strain as FLIP's. XPIC(1) is PIC: v* = v^n, and v^n + dt a = v^L.
!> State: the grid field kept in the cache's grid_work column 1 (v^n, then v* + dt a for G2P).
module mpm_xpic
   use mpm_kinds, only: dp
   use mpm_grid, only: grid_t
   use mpm_shape, only: shape_cache_t
   use mpm_particle_projection, only: projection_series, grid_scratch, velocity_of_momentum
   implicit none
   private
   public :: xpic_start, xpic_field

contains

   !> After the step's P2G: v^n = p_I/m_I into grid_work column 1.
   subroutine xpic_start(cache, grid)
      type(shape_cache_t), intent(inout) :: cache
      type(grid_t), intent(in) :: grid
      call grid_scratch(cache, grid)
      cache%grid_work(:, 1) = grid%momentum
      call velocity_of_momentum(grid, cache%grid_work(:, 1))
   end subroutine xpic_start

   !> After the grid solve: grid_work column 1 <- v* + dt a, the field G2P gives the particles' velocities.
   subroutine xpic_field(cache, mass_of, grid, dt)
      type(shape_cache_t), intent(inout) :: cache
      real(dp), intent(in), contiguous :: mass_of(:)
      type(grid_t), intent(in) :: grid
      real(dp), intent(in) :: dt
      call projection_series(cache%support, cache%first, cache%weight, mass_of, grid, cache%order, &
                             cache%grid_work(:, 1), cache%grid_work(:, 2), cache%grid_work(:, 3), cache%work(:, 1))
      cache%grid_work(:, 1) = cache%grid_work(:, 1) + dt*grid%acceleration
   end subroutine xpic_field
end module mpm_xpic
