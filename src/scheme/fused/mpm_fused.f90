!> The fused specialisation of USF, USL and MUSL for the paper's bar: linear shape functions, one
!> particle mass and volume, one material, no external force, the grid starting at x = 0. Each step
!> is one or two fused passes over the particles (mpm_transfer), which also carry the next step's
!> particle-to-grid transfer. The generic path (mpm_schemes over mpm_operations) is the definition;
!> these kernels are chosen automatically where they apply (mpm_simulation) and must agree with it
!> to round-off (test_generic).
module mpm_fused
   use mpm_kinds, only: dp
   use mpm_grid, only: grid_t, assemble_nodes, assemble_and_solve, nodal_velocity, solve_momentum
   use mpm_particles, only: particles_t
   use mpm_schemes, only: scheme_usf, scheme_usl, scheme_musl
   use mpm_transfer, only: pass_totals_t, p2g, fused_pass, pass_usf_stress, pass_usf_move, pass_usl, pass_musl_remap, &
                           pass_musl_stress, merge_totals
   implicit none
   private
   public :: fused_start, fused_step

contains

   !> Initial mapping: element shares of mass, momentum and (USL, MUSL) stress*volume.
   subroutine fused_start(scheme, particles, grid, totals)
      integer, intent(in) :: scheme
      type(particles_t), intent(inout) :: particles
      type(grid_t), intent(inout) :: grid
      type(pass_totals_t), intent(out) :: totals
      call p2g(particles, grid, scheme /= scheme_usf, totals)
   end subroutine fused_start

   !> One step; on entry the element shares hold this step's P2G, on exit the next step's.
   !> USF: nodal velocity -> stress update and its internal force -> momentum update -> G2P fused with
   !> the next mass and momentum shares. USL: momentum update -> one pass of G2P, stress update and the
   !> next P2G. MUSL: momentum update -> G2P with the new momentum mapped back -> nodal velocity ->
   !> stress update fused with the next P2G.
   subroutine fused_step(scheme, particles, grid, dt, youngs_modulus, totals)
      integer, intent(in) :: scheme
      type(particles_t), intent(inout) :: particles
      type(grid_t), intent(inout) :: grid
      real(dp), intent(in) :: dt, youngs_modulus
      type(pass_totals_t), intent(out) :: totals
      type(pass_totals_t) :: stress_totals
      select case (scheme)
      case (scheme_usf)
         call assemble_nodes(grid, .false.)
         call nodal_velocity(grid)
         call fused_pass(pass_usf_stress, particles, grid, dt, youngs_modulus, stress_totals)
         call solve_momentum(grid, dt, .true.)
         call fused_pass(pass_usf_move, particles, grid, dt, youngs_modulus, totals)
         call merge_totals(totals, stress_totals)
      case (scheme_usl)
         call assemble_and_solve(grid, dt)
         call fused_pass(pass_usl, particles, grid, dt, youngs_modulus, totals)
      case (scheme_musl)
         call assemble_and_solve(grid, dt)
         call fused_pass(pass_musl_remap, particles, grid, dt, youngs_modulus, totals)
         call assemble_nodes(grid, .false.)
         call nodal_velocity(grid)
         call fused_pass(pass_musl_stress, particles, grid, dt, youngs_modulus, stress_totals)
         call merge_totals(totals, stress_totals)
      end select
   end subroutine fused_step
end module mpm_fused
