!> The scheme layer: USF, USL and MUSL as docs/theory.md writes them (references there), over the generic operations of
!> mpm_operations (any shape function, per-particle masses, the problem's boundary conditions and forces).
!> - USF, Update Stress First ([Bardenhagen 2002]): the stress from the nodal velocities of this step's
!>   mapping, before the momentum update.
!> - USL, Update Stress Last: the stress from the nodal velocities after the momentum update.
!> - MUSL, Modified USL ([Sulsky 1995]): as USL, but the updated particle momentum is
!>   mapped back with the same shape functions and the stress uses the nodal velocity of that remap.
!> The transfers that need grid fields of their own (XPIC, FMPM, ASFLIP) act at three points of each step
!> (mpm_transfer_steps): after the P2G of mass and momentum, after a velocity formed outside the solve, and
!> after the solve.
!> The ladder is written once (generic_step), on one velocity field or on a field per body with
!> frictionless contact (mpm_contact); generic_stepper_t is the run's stepper on this path.
module mpm_schemes
   use mpm_kinds, only: dp
   use mpm_errors, only: error_t
   use mpm_grid, only: grid_t
   use mpm_particles, only: particles_t
   use mpm_shape, only: shape_cache_t, sync_cache
   use mpm_state, only: state_t
   use mpm_loads, only: loads_t
   use mpm_stepper, only: stepper_t, stepper_stop_t, scheme_usf, scheme_usl, scheme_musl, scheme_id
   use mpm_pass_totals, only: pass_totals_t
   use mpm_operations, only: locate_particles, p2g_mass_momentum, p2g_internal_force, nodal_velocities, &
                             solve_grid, g2p, update_stress, mirror_fold, particle_energies
   use mpm_contact, only: bodies_t, sync_bodies, bodies_init, locate_bodies, contact_velocities, &
                          contact_momentum, combine_bodies
   use mpm_material, only: material_t, law_hencky
   use mpm_transfer_steps, only: transfer_mapped, transfer_velocity_formed, transfer_solved
   implicit none
   private
   public :: scheme_usf, scheme_usl, scheme_musl, scheme_id, scheme_step, generic_stepper_t
   public :: generic_sync_state

   !> One step with the body's material, or with a Young's modulus alone (the hencky law).
   interface scheme_step
      module procedure scheme_step_material, scheme_step_hencky
   end interface scheme_step

   !> The explicit schemes on the generic operations: the shape functions of the step's start in `cache`,
   !> the bodies' `material`, and with `contact` a velocity field per body (`bodies`, made by `attach`).
   type, extends(stepper_t) :: generic_stepper_t
      type(shape_cache_t) :: cache
      type(material_t) :: material
      logical :: contact = .false.
      type(bodies_t) :: bodies
   contains
      procedure :: attach => generic_attach
      procedure :: start => generic_start
      procedure :: step => generic_stepper_step
      procedure :: displacement_mass => generic_mass
      procedure :: snapshot_grid => generic_snapshot_grid
      procedure :: stop_reason => generic_stop_reason
      procedure :: sync_state => generic_sync_state
   end type generic_stepper_t

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
      call generic_step(scheme, scene, cache, particles, grid, dt, &
                        material_t(law=law_hencky, youngs_modulus=youngs_modulus), t, totals)
   end subroutine scheme_step_hencky

   !> One step of `scheme` from time t to t + dt on one velocity field.
   subroutine scheme_step_material(scheme, scene, cache, particles, grid, dt, material, t, totals)
      integer, intent(in) :: scheme
      class(loads_t), intent(in) :: scene
      type(shape_cache_t), intent(inout) :: cache
      type(particles_t), intent(inout) :: particles
      type(grid_t), intent(inout) :: grid
      real(dp), intent(in) :: dt, t
      type(material_t), intent(in) :: material
      type(pass_totals_t), intent(out) :: totals
      call generic_step(scheme, scene, cache, particles, grid, dt, material, t, totals)
   end subroutine scheme_step_material

   !> One step of `scheme` from time t to t + dt; shape functions at the start-of-step positions. With
   !> `bodies`, the same operations on the stacked per-body fields, the contact correction after each
   !> nodal velocity (USF, MUSL's remap) and after the momentum update; the run's grid then holds the
   !> bodies' sum. USL on one field gathers the strain increment in G2P's loop, from the nodal velocities
   !> G2P used (it saves a gather); on the per-body fields the stress update gathers it itself.
   subroutine generic_step(scheme, loads, cache, particles, grid, dt, material, t, totals, bodies)
      integer, intent(in) :: scheme
      class(loads_t), intent(in) :: loads
      type(shape_cache_t), intent(inout) :: cache
      type(particles_t), intent(inout) :: particles
      type(grid_t), intent(inout) :: grid
      real(dp), intent(in) :: dt, t
      type(material_t), intent(in) :: material
      type(pass_totals_t), intent(out) :: totals
      type(bodies_t), intent(inout), optional :: bodies
      logical :: contact
      contact = present(bodies)
      if (contact) then
         call locate_bodies(cache, grid, particles, bodies, totals)
         call ladder(bodies%fields)
         call combine_bodies(bodies, grid)
      else
         call locate_particles(cache, grid, particles, totals)
         call ladder(grid)
      end if
   contains
      !> The scheme on the nodal fields f (the run's grid, or the bodies' stacked fields).
      subroutine ladder(f)
         type(grid_t), intent(inout) :: f
         select case (scheme)
         case (scheme_usf)
            call p2g_mass_momentum(cache, particles, f, with_force=.false.)
            call transfer_mapped(cache, particles, f)
            call velocities(f)
            call update_stress(cache, particles, f, dt, material, totals)
            call p2g_internal_force(cache, particles, f)
            call momentum_update(f)
            call g2p(cache, particles, f, dt, totals)
         case (scheme_usl)
            call p2g_mass_momentum(cache, particles, f, with_force=.true.)
            call transfer_mapped(cache, particles, f)
            call momentum_update(f)
            call g2p(cache, particles, f, dt, totals, strain_rate=.not. contact)
            call update_stress(cache, particles, f, dt, material, totals, strain_rate_gathered=.not. contact)
         case (scheme_musl)
            call p2g_mass_momentum(cache, particles, f, with_force=.true.)
            call transfer_mapped(cache, particles, f)
            call momentum_update(f)
            call g2p(cache, particles, f, dt, totals)
            call p2g_mass_momentum(cache, particles, f, with_force=.false.)  ! the remap: the new velocities
            call velocities(f)
            call update_stress(cache, particles, f, dt, material, totals)
         end select
      end subroutine ladder
      !> The nodal velocities of the mapping (and the bodies' contact correction; XPIC, FMPM and ASFLIP
      !> act after the mapping, after these velocities and after the solve: mpm_transfer_steps).
      subroutine velocities(f)
         type(grid_t), intent(inout) :: f
         call nodal_velocities(f)
         if (contact) call contact_velocities(bodies)
         call transfer_velocity_formed(cache, particles, f)
      end subroutine velocities
      !> The problem's external forces (when it has some), the force reflected at mirrored fixed ends
      !> (internal and external together: the image's body force is the mirror of the body's, as its
      !> displacement is), the explicit momentum update (and the bodies' contact correction).
      subroutine momentum_update(f)
         type(grid_t), intent(inout) :: f
         if (loads%external_forces) call loads%add_forces(f, t, cache, particles)
         call mirror_fold(f, .false., .true.)
         call solve_grid(f, dt)
         if (contact) call contact_momentum(bodies, dt)
         call transfer_solved(cache, particles, f, dt)
      end subroutine momentum_update
   end subroutine generic_step

   !> The per-body fields of the run's `grid` when the stepper has `contact` (after the grid is made).
   subroutine generic_attach(self, grid, particles, error)
      class(generic_stepper_t), intent(inout) :: self
      type(grid_t), intent(in) :: grid
      type(particles_t), intent(in) :: particles
      type(error_t), allocatable, intent(out) :: error
      if (self%contact) call bodies_init(self%bodies, grid, particles, error, element_shares=.false.)
   end subroutine generic_attach

   !> The generic path maps at each step's start: at t = 0 only the energies of the particles as they are.
   subroutine generic_start(self, loads, particles, grid, totals)
      class(generic_stepper_t), intent(inout) :: self
      class(loads_t), intent(in) :: loads
      type(particles_t), intent(inout) :: particles
      type(grid_t), intent(inout) :: grid
      type(pass_totals_t), intent(out) :: totals
      call particle_energies(particles, self%material, totals)
   end subroutine generic_start

   subroutine generic_stepper_step(self, loads, particles, grid, dt, t, totals)
      class(generic_stepper_t), intent(inout) :: self
      class(loads_t), intent(in) :: loads
      type(particles_t), intent(inout) :: particles
      type(grid_t), intent(inout) :: grid
      real(dp), intent(in) :: dt, t
      type(pass_totals_t), intent(out) :: totals
      if (self%contact) then
         call generic_step(self%scheme, loads, self%cache, particles, grid, dt, self%material, t, totals, self%bodies)
      else
         call generic_step(self%scheme, loads, self%cache, particles, grid, dt, self%material, t, totals)
      end if
   end subroutine generic_stepper_step

   !> The generic path sums m (x - X): u_cm is that over the total mass.
   real(dp) function generic_mass(self, particles)
      class(generic_stepper_t), intent(in) :: self
      type(particles_t), intent(in) :: particles
      generic_mass = sum(particles%mass_of)
   end function generic_mass

   !> At step 0 the nodal velocity p_I / m_I of the first mapping; later the grid holds the step's values.
   subroutine generic_snapshot_grid(self, particles, grid, step)
      class(generic_stepper_t), intent(inout) :: self
      type(particles_t), intent(in) :: particles
      type(grid_t), intent(inout) :: grid
      integer, intent(in) :: step
      type(pass_totals_t) :: unused
      if (step /= 0) return
      call locate_particles(self%cache, grid, particles, unused)
      call p2g_mass_momentum(self%cache, particles, grid, with_force=.false.)
      call nodal_velocities(grid)
   end subroutine generic_snapshot_grid
   !> A CPDI particle whose domain outgrew the nodes its weights reach (shape 'cpdi'; the guard stops).
   pure function generic_stop_reason(self) result(reason)
      class(generic_stepper_t), intent(in) :: self
      type(stepper_stop_t) :: reason
      reason = stepper_stop_t()
      reason%stretched = self%cache%stretched
   end function generic_stop_reason


   !> What the generic path carries from one step to the next: its shape cache (a total Lagrangian
   !> run's weights, CPDI corners, the transfers' grid fields) and the bodies' fields of a contact run.
   subroutine generic_sync_state(self, state)
      class(generic_stepper_t), intent(inout) :: self
      type(state_t), intent(inout) :: state
      call sync_cache(state, self%cache)
      if (self%contact) call sync_bodies(state, self%bodies)
   end subroutine generic_sync_state
end module mpm_schemes
