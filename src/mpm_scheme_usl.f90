!> Update Stress Last: P2G (mass, momentum, internal force from the current stress) -> momentum
!> update -> G2P (velocity with nodal acceleration, position with updated nodal velocity) ->
!> strain increment from the updated nodal velocity -> stress update.
module mpm_scheme_usl
   use mpm_kinds, only: dp
   use mpm_grid, only: grid_t, assemble_and_solve
   use mpm_particles, only: particles_t
   use mpm_transfer, only: pass_totals_t, p2g, g2p_stress_then_p2g
   implicit none
   private
   public :: usl_start, usl_step

contains

   !> Initial mapping: element shares of mass, momentum and stress*volume.
   subroutine usl_start(particles, grid, totals)
      type(particles_t), intent(inout) :: particles
      type(grid_t), intent(inout) :: grid
      type(pass_totals_t), intent(out) :: totals
      call p2g(particles, grid, .true., totals)
   end subroutine usl_start

   !> One USL step; on entry the element shares hold this step's P2G, on exit the next step's.
   subroutine usl_step(particles, grid, dt, youngs_modulus, totals)
      type(particles_t), intent(inout) :: particles
      type(grid_t), intent(inout) :: grid
      real(dp), intent(in) :: dt, youngs_modulus
      type(pass_totals_t), intent(out) :: totals
      call assemble_and_solve(grid, dt)
      call g2p_stress_then_p2g(particles, grid, dt, youngs_modulus, totals)
   end subroutine usl_step
end module mpm_scheme_usl
