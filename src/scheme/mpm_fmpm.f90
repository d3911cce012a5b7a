!> FMPM(k), the material point method with an approximate full mass matrix inverse ([Nairn & Hammerquist
!> 2021]; references: docs/theory.md): every velocity formed from a grid momentum q is
!>   v_k(q) = sum_{r<k} (I - A)^r M_L^-1 q
!> (A the particle projection, mpm_particle_projection; the series approximates A^-1 M_L^-1 q, the full
!> mass matrix's solve). So the particles' velocity is v_p = sum_I N_Ip v_k(p^L)_I and their position
!> x_p += dt sum_I N_Ip v_k(p^L)_I (G2P as PIC's on the filtered field), and the strain rate is taken from
!> v_k of the momentum the scheme uses (USL p^L, USF p before the update, MUSL the remapped momentum);
!> the forces are unchanged. FMPM(1) is PIC.
module mpm_fmpm
   use mpm_kinds, only: dp
   use mpm_grid, only: grid_t
   use mpm_shape, only: shape_cache_t
   use mpm_particle_projection, only: projection_series, grid_scratch
   implicit none
   private
   public :: fmpm_filter

contains

   !> grid%velocity (= M_L^-1 q of the momentum just formed) <- v_k(q).
   subroutine fmpm_filter(cache, mass_of, grid)
      type(shape_cache_t), intent(inout) :: cache
      real(dp), intent(in), contiguous :: mass_of(:)
      type(grid_t), intent(inout) :: grid
      if (cache%order <= 1) return
      call grid_scratch(cache, grid)
      cache%grid_work(:, 1) = grid%velocity
      call projection_series(cache%support, cache%first, cache%weight, mass_of, grid, cache%order, &
                             cache%grid_work(:, 1), cache%grid_work(:, 2), cache%grid_work(:, 3), cache%work(:, 1))
      grid%velocity = cache%grid_work(:, 1)
   end subroutine fmpm_filter
end module mpm_fmpm
