!> The scheme layer: USF, USL and MUSL as docs/theory.md writes them (references there), over the generic operations of
!> mpm_operations (any shape function, per-particle masses, the scene's boundary conditions and forces).
!> - USF, Update Stress First ([Bardenhagen 2002]): the stress from the nodal velocities of this step's
!>   mapping, before the momentum update.
!> - USL, Update Stress Last: the stress from the nodal velocities after the momentum update.
!> - MUSL, Modified USL ([Sulsky 1995]): as USL, but the updated particle momentum is
!>   mapped back with the same shape functions and the stress uses the nodal velocity of that remap.
!> The transfers that need grid fields of their own (XPIC, FMPM, ASFLIP) act at three points of each step
!> (mpm_transfer_steps): after the P2G of mass and momentum, after a velocity formed outside the solve, and
!> after the solve.
module mpm_schemes
   use mpm_kinds, only: dp
   use mpm_grid, only: grid_t
   use mpm_particles, only: particles_t
   use mpm_shape, only: shape_cache_t
   use mpm_loads, only: loads_t
   use mpm_diagnostics, only: pass_totals_t
   use mpm_operations, only: locate_particles, p2g_mass_momentum, p2g_internal_force, nodal_velocities, &
                             solve_grid, g2p, update_stress, mirror_fold
   use mpm_contact, only: bodies_t, locate_bodies, contact_velocities, contact_momentum, combine_bodies
   use mpm_material, only: material_t, law_hencky
   use mpm_transfer_steps, only: transfer_mapped, transfer_velocity_formed, transfer_solved
   implicit none
   private
   public :: scheme_usf, scheme_usl, scheme_musl, scheme_step, scheme_step_bodies

   integer, parameter :: scheme_usf = 1, scheme_usl = 2, scheme_musl = 3

   !> One step with the body's material, or with a Young's modulus alone (the hencky law).
   interface scheme_step
      module procedure scheme_step_material, scheme_step_hencky
   end interface scheme_step

contains

   !> scheme_step of a body of the hencky law with Young's modulus `youngs_modulus`.
   subroutine scheme_step_hencky(scheme, scene, cache, particles, grid, dt, youngs_modulus, t, totals)
      integer, intent(in) :: scheme
      class(loads_t), intent(in) :: scene
      type(shape_cache_t), intent(inout) :: cache
      type(particles_t), intent(inout) :: particles
      type(grid_t), intent(inout) :: grid
      real(dp), intent(in) :: dt, youngs_modulus, t
      type(pass_totals_t), intent(out) :: totals
      call scheme_step_material(scheme, scene, cache, particles, grid, dt, &
                                material_t(law=law_hencky, youngs_modulus=youngs_modulus), t, totals)
   end subroutine scheme_step_hencky

   !> One step of `scheme` from time t to t + dt; shape functions at the start-of-step positions.
   subroutine scheme_step_material(scheme, scene, cache, particles, grid, dt, material, t, totals)
      integer, intent(in) :: scheme
      class(loads_t), intent(in) :: scene
      type(shape_cache_t), intent(inout) :: cache
      type(particles_t), intent(inout) :: particles
      type(grid_t), intent(inout) :: grid
      real(dp), intent(in) :: dt, t
      type(material_t), intent(in) :: material
      type(pass_totals_t), intent(out) :: totals
      call locate_particles(cache, grid, particles, totals)
      select case (scheme)
      case (scheme_usf)
         call p2g_mass_momentum(cache, particles, grid, with_force=.false.)
         call transfer_mapped(cache, particles, grid)
         call nodal_velocities(grid)
         call transfer_velocity_formed(cache, particles, grid)
         call update_stress(cache, particles, grid, dt, material, totals)
         call p2g_internal_force(cache, particles, grid)
         call momentum_update()
         call g2p(cache, particles, grid, dt, totals)
      case (scheme_usl)
         call p2g_mass_momentum(cache, particles, grid, with_force=.true.)
         call transfer_mapped(cache, particles, grid)
         call momentum_update()
         ! (the strain increment uses the nodal velocities G2P used: gathered there, in the same loop)
         call g2p(cache, particles, grid, dt, totals, strain_rate=.true.)
         call update_stress(cache, particles, grid, dt, material, totals, strain_rate_gathered=.true.)
      case (scheme_musl)
         call p2g_mass_momentum(cache, particles, grid, with_force=.true.)
         call transfer_mapped(cache, particles, grid)
         call momentum_update()
         call g2p(cache, particles, grid, dt, totals)
         call p2g_mass_momentum(cache, particles, grid, with_force=.false.)  ! the remap: the new velocities
         call nodal_velocities(grid)
         call transfer_velocity_formed(cache, particles, grid)
         call update_stress(cache, particles, grid, dt, material, totals)
      end select
   contains
      !> The scene's external forces (when it has some), the force reflected at mirrored fixed ends
      !> (internal and external together: the image's body force is the mirror of the body's, as its
      !> displacement is), and the explicit momentum update.
      subroutine momentum_update()
         if (scene%external_forces) call scene%add_forces(grid, t, cache, particles)
         call mirror_fold(grid, .false., .true.)
         call solve_grid(grid, dt)
         call transfer_solved(cache, particles, grid, dt)
      end subroutine momentum_update
   end subroutine scheme_step_material

   !> scheme_step with a velocity field per body and frictionless contact (mpm_contact): the same
   !> operations on the stacked per-body fields, the contact correction after each nodal velocity
   !> (USF, MUSL's remap) and after the momentum update; the run's grid then holds the bodies' sum.
   subroutine scheme_step_bodies(scheme, scene, cache, particles, grid, bodies, dt, material, t, totals)
      integer, intent(in) :: scheme
      class(loads_t), intent(in) :: scene
      type(shape_cache_t), intent(inout) :: cache
      type(particles_t), intent(inout) :: particles
      type(grid_t), intent(inout) :: grid
      type(bodies_t), intent(inout) :: bodies
      real(dp), intent(in) :: dt, t
      type(material_t), intent(in) :: material
      type(pass_totals_t), intent(out) :: totals
      call locate_bodies(cache, grid, particles, bodies, totals)
      select case (scheme)
      case (scheme_usf)
         call p2g_mass_momentum(cache, particles, bodies%fields, with_force=.false.)
         call nodal_velocities(bodies%fields)
         call contact_velocities(bodies)
         call update_stress(cache, particles, bodies%fields, dt, material, totals)
         call p2g_internal_force(cache, particles, bodies%fields)
         call momentum_update()
         call g2p(cache, particles, bodies%fields, dt, totals)
      case (scheme_usl)
         call p2g_mass_momentum(cache, particles, bodies%fields, with_force=.true.)
         call momentum_update()
         call g2p(cache, particles, bodies%fields, dt, totals)
         call update_stress(cache, particles, bodies%fields, dt, material, totals)
      case (scheme_musl)
         call p2g_mass_momentum(cache, particles, bodies%fields, with_force=.true.)
         call momentum_update()
         call g2p(cache, particles, bodies%fields, dt, totals)
         call p2g_mass_momentum(cache, particles, bodies%fields, with_force=.false.)
         call nodal_velocities(bodies%fields)
         call contact_velocities(bodies)
         call update_stress(cache, particles, bodies%fields, dt, material, totals)
      end select
      call combine_bodies(bodies, grid)
   contains
      subroutine momentum_update()
         if (scene%external_forces) call scene%add_forces(bodies%fields, t, cache, particles)
         call mirror_fold(bodies%fields, .false., .true.)
         call solve_grid(bodies%fields, dt)
         call contact_momentum(bodies, dt)
      end subroutine momentum_update
   end subroutine scheme_step_bodies
end module mpm_schemes
