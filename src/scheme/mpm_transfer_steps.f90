!> Where the transfers beyond FLIP, PIC, the blend and APIC act in a step: XPIC(m) (mpm_xpic), FMPM(k)
!> (mpm_fmpm) and ASFLIP (mpm_asflip) each need a grid field at a point of the step other than G2P. The
!> schemes call these three at fixed points of every step; a run of another transfer does nothing in them.
module mpm_transfer_steps
   use mpm_kinds, only: dp
   use mpm_grid, only: grid_t
   use mpm_particles, only: particles_t
   use mpm_shape, only: shape_cache_t, transfer_xpic, transfer_fmpm, transfer_asflip
   use mpm_xpic, only: xpic_start, xpic_field
   use mpm_fmpm, only: fmpm_filter
   use mpm_asflip, only: asflip_start
   implicit none
   private
   public :: transfer_mapped, transfer_velocity_formed, transfer_solved

contains

   !> After the step's P2G of mass and momentum, before any force update: XPIC and ASFLIP keep v^n = p/m
   !> (ASFLIP also each particle's J^n).
   subroutine transfer_mapped(cache, particles, grid)
      type(shape_cache_t), intent(inout) :: cache
      type(particles_t), intent(in) :: particles
      type(grid_t), intent(in) :: grid
      select case (cache%transfer)
      case (transfer_xpic)
         call xpic_start(cache, grid)
      case (transfer_asflip)
         call asflip_start(cache, grid, particles%volume_ratio)
      end select
   end subroutine transfer_mapped

   !> After a grid velocity was formed from a momentum outside the solve (USF's v^n, MUSL's remap): FMPM
   !> filters it.
   subroutine transfer_velocity_formed(cache, particles, grid)
      type(shape_cache_t), intent(inout) :: cache
      type(particles_t), intent(in) :: particles
      type(grid_t), intent(inout) :: grid
      if (cache%transfer == transfer_fmpm) call fmpm_filter(cache, particles%mass_of, grid)
   end subroutine transfer_velocity_formed

   !> After the grid solve (p^L, a, v^L): XPIC forms v* + dt a for G2P, FMPM filters v^L.
   subroutine transfer_solved(cache, particles, grid, dt)
      type(shape_cache_t), intent(inout) :: cache
      type(particles_t), intent(in) :: particles
      type(grid_t), intent(inout) :: grid
      real(dp), intent(in) :: dt
      select case (cache%transfer)
      case (transfer_xpic)
         call xpic_field(cache, particles%mass_of, grid, dt)
      case (transfer_fmpm)
         call fmpm_filter(cache, particles%mass_of, grid)
      end select
   end subroutine transfer_solved
end module mpm_transfer_steps
