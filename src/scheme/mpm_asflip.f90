!> ASFLIP, the affine-separable FLIP ([Fei 2021]; references: docs/theory.md), in 1-D without its affine
!> part: with v_old = sum_I N_Ip v^n_I (the step's P2G velocity, before the force update) and
!> v_PIC = sum_I N_Ip v^L_I,
!>   v_p <- v_PIC + alpha (v_p - v_old),
!>   x_p += dt (v_PIC + beta alpha (v_p^n - v_old)),
!> beta = 1 where the particle separates, ln J_p^n + dt sum_I dN_Ip v^L_I >= -1e-3 (the volume it would have
!> after a step with the grid), else 0 (it moves with the grid). alpha = 0 is PIC; alpha = 1 gives FLIP's
!> velocity. State: v^n in the cache's grid_work column 1 and J^n per particle (its start_volume_ratio).
module mpm_asflip
   use mpm_kinds, only: dp
   use mpm_grid, only: grid_t
   use mpm_shape, only: shape_cache_t
   use mpm_particle_projection, only: grid_scratch, velocity_of_momentum
   implicit none
   private
   public :: asflip_start, asflip_update, separation_threshold

   !> A particle whose ln J after a step with the grid would fall below this moves with the grid (beta = 0).
   real(dp), parameter :: separation_threshold = -1.0e-3_dp

contains

   !> After the step's P2G: v^n = p_I/m_I into grid_work column 1, and each particle's J^n.
   subroutine asflip_start(cache, grid, volume_ratio)
      type(shape_cache_t), intent(inout) :: cache
      type(grid_t), intent(in) :: grid
      real(dp), intent(in), contiguous :: volume_ratio(:)
      call grid_scratch(cache, grid)
      cache%grid_work(:, 1) = grid%momentum
      call velocity_of_momentum(grid, cache%grid_work(:, 1))
      cache%start_volume_ratio = volume_ratio
   end subroutine asflip_start

   !> G2P's update from the gathered sums (column 1 sum N v^n, 2 sum N v^L, 3 sum dN v^L): the particles'
   !> velocities, and column 2 becomes the velocity they move with.
   pure subroutine asflip_update(alpha, dt, start_volume_ratio, v, gathered)
      real(dp), intent(in) :: alpha, dt
      real(dp), intent(in), contiguous :: start_volume_ratio(:)
      real(dp), intent(inout), contiguous :: v(:), gathered(:, :)
      integer :: p
      real(dp) :: offset
      do p = 1, size(v)
         offset = alpha*(v(p) - gathered(p, 1))
         v(p) = gathered(p, 2) + offset
         if (log(start_volume_ratio(p)) + dt*gathered(p, 3) >= separation_threshold) &
            gathered(p, 2) = gathered(p, 2) + offset
      end do
   end subroutine asflip_update
end module mpm_asflip
