!> Modified USL (Sulsky et al.): as USL, but after G2P the updated particle momentum is mapped back
!> to the grid (fixed node held) and the strain increment uses the nodal velocity of that remap.
module mpm_scheme_musl
   use mpm_kinds, only: dp
   use mpm_grid, only: grid_t, assemble_nodes, assemble_and_solve, nodal_velocity
   use mpm_particles, only: particles_t
   use mpm_transfer, only: pass_totals_t, p2g, g2p_with_remap, stress_then_p2g, merge_totals
   implicit none
   private
   public :: musl_start, musl_step

contains

   !> Initial mapping: element shares of mass, momentum and stress*volume.
   subroutine musl_start(particles, grid, totals)
      type(particles_t), intent(inout) :: particles
      type(grid_t), intent(inout) :: grid
      type(pass_totals_t), intent(out) :: totals
      call p2g(particles, grid, .true., totals)
   end subroutine musl_start

   !> One MUSL step; on entry the element shares hold this step's P2G, on exit the next step's.
   subroutine musl_step(particles, grid, dt, youngs_modulus, totals)
      type(particles_t), intent(inout) :: particles
      type(grid_t), intent(inout) :: grid
      real(dp), intent(in) :: dt, youngs_modulus
      type(pass_totals_t), intent(out) :: totals
      type(pass_totals_t) :: stress_totals
      call assemble_and_solve(grid, dt)
      call g2p_with_remap(particles, grid, dt, totals)
      call assemble_nodes(grid, .false.)
      call nodal_velocity(grid)
      call stress_then_p2g(particles, grid, dt, youngs_modulus, stress_totals)
      call merge_totals(totals, stress_totals)
   end subroutine musl_step
end module mpm_scheme_musl
