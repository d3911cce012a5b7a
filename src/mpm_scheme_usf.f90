!> Update Stress First: P2G (mass, momentum) -> nodal velocity -> strain increment and stress
!> update -> internal force from the new stress -> momentum update -> G2P.
module mpm_scheme_usf
   use mpm_kinds, only: dp
   use mpm_grid, only: grid_t, assemble_nodes, nodal_velocity, solve_momentum
   use mpm_particles, only: particles_t
   use mpm_transfer, only: pass_totals_t, p2g, stress_then_force, g2p_then_p2g, merge_totals
   implicit none
   private
   public :: usf_start, usf_step

contains

   !> Initial mapping: element shares of mass and momentum.
   subroutine usf_start(particles, grid, totals)
      type(particles_t), intent(inout) :: particles
      type(grid_t), intent(inout) :: grid
      type(pass_totals_t), intent(out) :: totals
      call p2g(particles, grid, .false., totals)
   end subroutine usf_start

   !> One USF step; on entry the element shares hold this step's mass and momentum, on exit the next step's.
   subroutine usf_step(particles, grid, dt, youngs_modulus, totals)
      type(particles_t), intent(inout) :: particles
      type(grid_t), intent(inout) :: grid
      real(dp), intent(in) :: dt, youngs_modulus
      type(pass_totals_t), intent(out) :: totals
      type(pass_totals_t) :: stress_totals
      call assemble_nodes(grid, .false.)
      call nodal_velocity(grid)
      call stress_then_force(particles, grid, dt, youngs_modulus, stress_totals)
      call solve_momentum(grid, dt, .true.)
      call g2p_then_p2g(particles, grid, dt, totals)
      call merge_totals(totals, stress_totals)
   end subroutine usf_step
end module mpm_scheme_usf
