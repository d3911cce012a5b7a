!> A generic operation for forces that differ between particles (body forces that depend on the
!> particle's position or reference position and on time): f_I += sum_p N_Ip f_p with the step's shape
!> functions. Scenes call it from their add_forces hook; nothing else runs it, so a scene without
!> such forces pays nothing. Kept apart from mpm_operations so that the two evolve independently.
module mpm_particle_forces
   use mpm_kinds, only: dp
   use mpm_grid, only: grid_t
   use mpm_shape, only: shape_cache_t
   implicit none
   private
   public :: p2g_particle_forces

contains

   !> grid%force(I) += sum_p N_Ip forces(p) (forces in N per unit area, one per particle).
   subroutine p2g_particle_forces(cache, forces, grid)
      type(shape_cache_t), intent(in) :: cache
      real(dp), intent(in), contiguous :: forces(:)
      type(grid_t), intent(inout) :: grid
      call scatter_forces(cache%support, cache%first, cache%weight, forces, grid%force)
   end subroutine p2g_particle_forces

   subroutine scatter_forces(support, first, weight, forces, force)
      integer, intent(in) :: support
      integer, intent(in), contiguous :: first(:)
      real(dp), intent(in), contiguous :: weight(:, :), forces(:)
      real(dp), intent(inout), contiguous :: force(0:)
      integer :: p, k, i
      do p = 1, size(first)
         do k = 1, support
            i = first(p) + k - 1
            force(i) = force(i) + weight(p, k)*forces(p)
         end do
      end do
   end subroutine scatter_forces
end module mpm_particle_forces
