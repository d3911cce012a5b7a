!> The fused specialisation of USF, USL and MUSL: the paper's bar with any shape function (linear; the
!> wide ones as particles in parts, see mpm_transfer) and FLIP, one particle mass, volume and modulus,
!> and, with the hat, its variants: PIC, the blend and APIC; per-particle masses and moduli (a composite
!> bar); per-particle external forces (a manufactured solution); bodies on stacked fields with
!> frictionless contact, or a grid origin left of x = 0 (an impact). The scene's grid loads (a body
!> acceleration, a driven node) are applied where the nodal force is assembled (mpm_grid). Each step is
!> one or two fused passes over the particles (mpm_transfer), which also carry the next step's
!> particle-to-grid transfer. The generic path (mpm_schemes over mpm_operations) is the definition;
!> these kernels are chosen automatically where they apply (fused_choose, from mpm_simulation) and must
!> agree with it to round-off (test_fused_bar, test_fused_shapes, test_fused_scenes).
module mpm_fused
   use mpm_kinds, only: dp
   use mpm_grid, only: grid_t, assemble_nodes, assemble_and_solve, nodal_velocity, solve_momentum, element_forces, &
                       nodal_kinematics
   use mpm_operations, only: mirror_fold
   use mpm_particles, only: particles_t
   use mpm_shape, only: shape_linear, shape_cpgimp, shape_bspline2, shape_bspline3, shape_cpdi, transfer_flip, &
                        transfer_pic, transfer_blend, transfer_apic, transfer_asflip, transfer_xpic, &
                        transfer_fmpm
   use mpm_errors, only: error_t
   use mpm_pass_totals, only: pass_totals_t
   use mpm_stepper, only: stepper_t, scheme_usf, scheme_usl, scheme_musl
   use mpm_material, only: material_t, law_linear, law_elastoplastic
   use mpm_loads, only: loads_t
   use mpm_state, only: state_t
   use mpm_segments, only: segments_t, sync_segments
   use mpm_contact, only: bodies_t, sync_bodies, bodies_init, touch_test, contact_correct, combine_bodies
   use mpm_transfer, only: p2g, fused_pass, pass_usf_stress, pass_usf_move, pass_usl, pass_musl_remap, &
                           pass_musl_stress, pass_map, pass_map_stress, merge_totals, fused_box_t, box_cells, &
                           locate_all, variant_bar, variant_pic, variant_blend, variant_apic, variant_material, &
                           variant_forced, variant_bodies, variant_asflip, variant_total, variant_xpic, &
                           body_of_element, asflip_separation
   use mpm_fused_projection, only: fused_projection_series
   use mpm_particle_projection, only: velocity_of_momentum
   implicit none
   private
   public :: fused_start, fused_step, fused_box_t, fused_shape, fused_choose, fused_mass, fused_grid_velocity, &
             fused_grid_sum, fused_stepper_t

   !> The run's stepper on the fused kernels: the kernels' description of the run (`box`, from
   !> fused_choose), the one Young's modulus of the bar's kernels, the particle passes' work split
   !> (`segments`, planned at the start), and the bodies' stacked fields where each body has its own
   !> (`contact`, made by `attach`).
   type, extends(stepper_t) :: fused_stepper_t
      type(fused_box_t) :: box
      type(segments_t) :: segments
      real(dp) :: youngs_modulus = 0.0_dp
      logical :: contact = .false.
      type(bodies_t) :: bodies
   contains
      procedure :: attach => fused_attach
      procedure :: start => fused_stepper_start
      procedure :: step => fused_stepper_step
      procedure :: displacement_mass => fused_stepper_mass
      procedure :: snapshot_grid => fused_snapshot_grid
      procedure :: sync_state => fused_sync_state
   end type fused_stepper_t

contains

   !> The bodies' stacked fields, with the kernels' element shares, when the stepper has `contact`
   !> (after the run's grid is made).
   subroutine fused_attach(self, grid, particles, error)
      class(fused_stepper_t), intent(inout) :: self
      type(grid_t), intent(in) :: grid
      type(particles_t), intent(in) :: particles
      type(error_t), allocatable, intent(out) :: error
      if (self%contact) call bodies_init(self%bodies, grid, particles, error, element_shares=.true.)
   end subroutine fused_attach

   subroutine fused_stepper_start(self, loads, particles, grid, totals)
      class(fused_stepper_t), intent(inout) :: self
      class(loads_t), intent(in) :: loads
      type(particles_t), intent(inout) :: particles
      type(grid_t), intent(inout) :: grid
      type(pass_totals_t), intent(out) :: totals
      call fused_start(self%scheme, particles, grid, self%segments, totals, self%box, self%youngs_modulus, loads, &
                       self%bodies)
   end subroutine fused_stepper_start

   subroutine fused_stepper_step(self, loads, particles, grid, dt, t, totals)
      class(fused_stepper_t), intent(inout) :: self
      class(loads_t), intent(in) :: loads
      type(particles_t), intent(inout) :: particles
      type(grid_t), intent(inout) :: grid
      real(dp), intent(in) :: dt, t
      type(pass_totals_t), intent(out) :: totals
      type(pass_totals_t) :: stress_totals
      if (.not. plain_step(self%box)) then
         call fused_step(self%scheme, particles, grid, self%segments, dt, self%youngs_modulus, totals, self%box, loads, &
                         t, self%bodies)
         return
      end if
      ! fused_step's sequence of a step that needs none of its extras, here: four calls fewer (fused_step,
      ! step_on, solve, pass), which a small run (the paper's sweep: 1-50 elements) pays at every step
      associate (seg => self%segments, box => self%box, modulus => self%youngs_modulus)
         select case (self%scheme)
         case (scheme_usf)
            call nodal_kinematics(grid)
            call fused_pass(pass_usf_stress, particles, grid, seg, dt, modulus, stress_totals, box)
            call solve_momentum(grid, dt, .true.)
            call fused_pass(pass_usf_move, particles, grid, seg, dt, modulus, totals, box)
            call merge_totals(totals, stress_totals)
         case (scheme_usl)
            call assemble_and_solve(grid, dt)
            call fused_pass(pass_usl, particles, grid, seg, dt, modulus, totals, box)
         case (scheme_musl)
            call assemble_and_solve(grid, dt)
            call fused_pass(pass_musl_remap, particles, grid, seg, dt, modulus, totals, box)
            call nodal_kinematics(grid)
            call fused_pass(pass_musl_stress, particles, grid, seg, dt, modulus, stress_totals, box)
            call merge_totals(totals, stress_totals)
         end select
      end associate
   end subroutine fused_stepper_step

   !> Whether a step with `box` (after fused_start) is fused_step's plain sequence: the particles' passes
   !> and the grid's assembly and solve on the run's grid, none of the wide shapes' mirror, bodies'
   !> stacked fields and contact, per-particle forces, ASFLIP's, XPIC's or FMPM's nodal fields.
   pure logical function plain_step(box)
      type(fused_box_t), intent(in) :: box
      plain_step = .not. (box%parts .or. box%fmpm .or. on_stacked_fields(box) .or. .not. allocated(box%carry)) &
                   .and. box%variant /= variant_forced .and. box%variant /= variant_asflip .and. &
                   box%variant /= variant_xpic
   end function plain_step

   real(dp) function fused_stepper_mass(self, particles)
      class(fused_stepper_t), intent(in) :: self
      type(particles_t), intent(in) :: particles
      fused_stepper_mass = fused_mass(particles, self%box)
   end function fused_stepper_mass

   !> At step 0 the nodal velocity of the first mapping; later, bodies on stacked fields summed on the
   !> run's grid (fused_step leaves it as it was: only a snapshot reads it).
   subroutine fused_snapshot_grid(self, particles, grid, step)
      class(fused_stepper_t), intent(inout) :: self
      type(particles_t), intent(in) :: particles
      type(grid_t), intent(inout) :: grid
      integer, intent(in) :: step
      if (step == 0) then
         call fused_grid_velocity(grid, self%box, self%bodies)
      else
         call fused_grid_sum(grid, self%box, self%bodies)
      end if
   end subroutine fused_snapshot_grid

   !> Whether the fused kernels take a run of shape `kind` (mpm_shape's ids), transfer `transfer` (its
   !> FLIP fraction for the blend) of a problem with loads `loads`, its placed `particles` and `material`
   !> (every law: hencky, linear, elastoplastic), where the problem allows them (`applies`: the scene's
   !> fused_applies) and with a velocity field per body when `body_fields`, and if so `box`, the kernels'
   !> description of it (fused_box_t: the shape, the variant of the hat's kernels, the law). They take:
   !> - the bar and a scene whose forces are grid loads (the column), every shape with FLIP, the hat with
   !>   PIC, the blend, APIC and ASFLIP: particles of one mass and volume (no per-particle arrays);
   !> - with the hat and FLIP: per-particle masses and moduli of one volume (the composite bar), per-
   !>   particle forces (the manufactured solution), bodies each of one mass, volume and modulus, on
   !>   stacked fields or in one field (the impact);
   !> - the hat with XPIC (its variant), and with FMPM (PIC's kernels on filtered velocities) when `scheme`
   !>   is given and is USF or USL (MUSL's remapped velocity would need the particles' start-of-step
   !>   positions after they moved), as PIC: particles of one mass and volume.
   !> With `total` (the total-Lagrangian formulation) only the first kind, with the hat and FLIP (variant
   !> total: the bar and the column).
   !> Anything else runs on the generic path.
   function fused_choose(kind, transfer, flip_fraction, applies, body_fields, loads, particles, material, total, &
                         scheme) result(box)
      integer, intent(in) :: kind, transfer
      integer, intent(in), optional :: scheme
      real(dp), intent(in) :: flip_fraction
      logical, intent(in) :: applies, body_fields
      class(loads_t), intent(in) :: loads
      type(particles_t), intent(in) :: particles
      type(material_t), intent(in) :: material
      logical, intent(in), optional :: total
      type(fused_box_t) :: box
      logical :: hat_flip, per_particle
      box = fused_shape(kind)
      box%variant = -1  ! (none: the generic path)
      box%flip_fraction = flip_fraction
      box%linear = material%law == law_linear
      box%plastic = material%law == law_elastoplastic
      box%yield_stress = material%yield_stress
      box%hardening_modulus = material%hardening_modulus
      if (.not. applies .or. kind == shape_cpdi) return ! (CPDI's weights follow moving corners)
      hat_flip = kind == shape_linear .and. transfer == transfer_flip
      per_particle = allocated(particles%mass_of) .or. allocated(particles%volume0_of) .or. &
                     allocated(particles%youngs_modulus_of)
      if (present(total)) then
         if (total) then
            if (hat_flip .and. .not. (per_particle .or. allocated(particles%body) .or. loads%has_particle_forces)) &
               box%variant = variant_total
            return
         end if
      end if
      if (allocated(particles%body)) then ! bodies, each of one mass, volume and modulus
         ! (on stacked fields each its own; in one field, as one body: the same for all)
         if (hat_flip .and. bodies_uniform(particles, .not. body_fields)) box%variant = variant_bodies
      else if (loads%has_particle_forces) then
         if (hat_flip .and. .not. per_particle) box%variant = variant_forced
      else if (per_particle) then ! several materials of one particle volume
         if (hat_flip .and. allocated(particles%mass_of) .and. allocated(particles%youngs_modulus_of)) then
            if (.not. allocated(particles%volume0_of)) then
               box%variant = variant_material
            else if (all(particles%volume0_of == particles%volume0)) then
               box%variant = variant_material
            end if
         end if
      else
         select case (transfer)
         case (transfer_flip)
            box%variant = variant_bar
         case (transfer_pic)
            if (kind == shape_linear) box%variant = variant_pic
         case (transfer_blend)
            if (kind == shape_linear) box%variant = variant_blend
         case (transfer_apic)
            if (kind == shape_linear) box%variant = variant_apic
         case (transfer_asflip) ! (its alpha: box%asflip_alpha, set by the caller)
            if (kind == shape_linear) box%variant = variant_asflip
         case (transfer_xpic)
            if (kind == shape_linear) box%variant = variant_xpic
         case (transfer_fmpm)
            if (kind == shape_linear .and. present(scheme)) then
               box%fmpm = scheme == scheme_usf .or. scheme == scheme_usl
               if (box%fmpm) box%variant = variant_pic
            end if
         end select
      end if
   end function fused_choose

   !> Each body (a contiguous range of particles%body) has one mass, volume and modulus, and where the
   !> particles carry them one yield stress and hardening modulus (`together`: all bodies the same).
   pure logical function bodies_uniform(particles, together) result(uniform)
      type(particles_t), intent(in) :: particles
      logical, intent(in) :: together
      integer :: p
      uniform = allocated(particles%mass_of) .and. allocated(particles%volume0_of) .and. &
                allocated(particles%youngs_modulus_of)
      if (.not. uniform) return
      do p = 2, particles%count
         if (particles%body(p) /= particles%body(p - 1) .and. .not. together) cycle
         if (particles%mass_of(p) /= particles%mass_of(p - 1) .or. particles%volume0_of(p) /= particles%volume0_of(p - 1) &
             .or. particles%youngs_modulus_of(p) /= particles%youngs_modulus_of(p - 1)) then
            uniform = .false.
            return
         end if
         if (allocated(particles%yield_stress_of)) then
            if (particles%yield_stress_of(p) /= particles%yield_stress_of(p - 1) .or. &
                particles%hardening_modulus_of(p) /= particles%hardening_modulus_of(p - 1)) then
               uniform = .false.
               return
            end if
         end if
      end do
   end function bodies_uniform

   !> What the fused kernels' totals%displacement is divided by for u_cm: the particle count where every
   !> particle has the run's one mass (the kernels sum x - X), else the total mass (they sum m (x - X)).
   pure real(dp) function fused_mass(particles, box) result(mass)
      type(particles_t), intent(in) :: particles
      type(fused_box_t), intent(in) :: box
      if (box%variant == variant_material .or. box%variant == variant_bodies) then
         if (allocated(particles%mass_of)) then
            mass = sum(particles%mass_of)
            return
         end if
      end if
      mass = particles%count
   end function fused_mass

   !> Initial mapping: element shares of mass, momentum and (USL, MUSL) stress*volume. With particles
   !> in parts (`box`, and the run's `youngs_modulus`): a USL pass of zero time step, which moves
   !> nothing and maps the parts where they are (x + 0, v + 0, sigma + E 0, J (1 + 0) leave every value
   !> as it is). The hat's variants: each particle's cell, then the mapping passes pass_map(_stress)
   !> (with the scene's forces at t = 0; bodies: on the stacked fields of `bodies`, whose element shares
   !> are made here) and the energies of the particles as they are. The scene's grid loads are set here.
   subroutine fused_start(scheme, particles, grid, seg, totals, box, youngs_modulus, scene, bodies)
      integer, intent(in) :: scheme
      type(particles_t), intent(inout) :: particles
      type(grid_t), intent(inout) :: grid
      !> the run's segments (planned here)
      type(segments_t), intent(inout) :: seg
      type(pass_totals_t), intent(out) :: totals
      type(fused_box_t), intent(inout), optional :: box
      real(dp), intent(in), optional :: youngs_modulus
      class(loads_t), intent(in), optional :: scene
      type(bodies_t), intent(inout), optional :: bodies
      seg = segments_t() ! (planned afresh: the segments of an earlier run with other particles mean nothing here)
      if (present(scene)) grid%loads = scene%grid_loads()
      if (present(box)) then
         if (box%variant /= variant_bar) then
            if (box%variant == variant_bodies) then
               call start_bodies(box, particles, grid, bodies)
               if (on_stacked_fields(box)) then
                  call start_variant(bodies%fields)
               else
                  call start_variant(grid)
               end if
            else
               call start_variant(grid)
            end if
            return
         end if
         if (box%parts) then
            if (scheme /= scheme_usl .and. .not. allocated(box%carry)) allocate (box%carry(particles%count))
            if (.not. allocated(box%carry)) allocate (box%carry(0))
            call box_cells(particles, grid, box)
            call fused_pass(pass_usl, particles, grid, seg, 0.0_dp, youngs_modulus, totals, box)
            return
         end if
         ! the hat's passes take it too (no carry), so that no pass allocates one
         if (.not. allocated(box%carry)) allocate (box%carry(0))
      end if
      call p2g(particles, grid, seg, scheme /= scheme_usf, totals)
   contains
      subroutine start_variant(fields)
         type(grid_t), intent(inout) :: fields
         type(pass_totals_t) :: map_totals
         if (box%variant == variant_asflip) then ! v^n of each step's mapping; USF: J^n between its passes
            if (.not. allocated(box%mapped_velocity)) allocate (box%mapped_velocity(0:fields%elements), &
                                                                box%separating(fields%elements))
            if (scheme == scheme_usf .and. .not. allocated(box%carry)) allocate (box%carry(particles%count))
         end if
         if (.not. allocated(box%carry)) allocate (box%carry(0))
         if (box%variant == variant_xpic .or. box%fmpm) then ! the series' grid scratch, once
            if (.not. allocated(box%series_field)) allocate (box%series_field(0:fields%elements), &
                                                             box%series_term(0:fields%elements), &
                                                             box%series_projected(0:fields%elements))
         end if
         if (box%variant == variant_forced) then
            allocate (box%forces(particles%count))
            call element_forces(fields)
         end if
         call locate_all(particles, fields, seg, box)
         if (box%variant == variant_forced) call scene%particle_forces(0.0_dp, particles, box%forces)
         call fused_pass(merge(pass_map, pass_map_stress, scheme == scheme_usf), particles, fields, seg, 0.0_dp, &
                         youngs_modulus, map_totals, box)
         call initial_energies(particles, youngs_modulus, totals)
         totals%outside = map_totals%outside
      end subroutine start_variant
   end subroutine fused_start

   !> The bodies' description for the kernels (variant_bodies): each body's particles, mass, volume and
   !> modulus (and yield stress and hardening modulus: the elastoplastic law), and where its field begins
   !> in the stacked fields of `bodies` (allocated with element shares by bodies_init); without stacked
   !> fields (bodies%count = 0: one velocity field) all the particles as one body on the run's grid.
   subroutine start_bodies(box, particles, grid, bodies)
      type(fused_box_t), intent(inout) :: box
      type(particles_t), intent(in) :: particles
      type(grid_t), intent(in) :: grid
      type(bodies_t), intent(inout) :: bodies
      integer :: b
      if (bodies%count == 0) then
         box%body_first = [1]
         box%body_last = [particles%count]
         box%body_mass = [particles%mass_of(1)]
         box%body_volume0 = [particles%volume0_of(1)]
         box%body_modulus = [particles%youngs_modulus_of(1)]
         box%body_element = [1]
         box%body_cells = grid%elements
         call body_laws([1])
         return
      end if
      associate (n => bodies%count)
         box%body_first = bodies%first
         box%body_last = bodies%last
         box%body_mass = particles%mass_of(bodies%first)
         box%body_volume0 = particles%volume0_of(bodies%first)
         box%body_modulus = particles%youngs_modulus_of(bodies%first)
         box%body_element = [((b - 1)*bodies%nodes + 1, b=1, n)]
         box%body_cells = bodies%nodes - 1
         call body_laws(bodies%first)
      end associate
   contains
      !> Each body's yield stress and hardening modulus, its first particle's (the run's where the
      !> particles carry none).
      subroutine body_laws(firsts)
         integer, intent(in) :: firsts(:)
         if (allocated(particles%yield_stress_of)) then
            box%body_yield = particles%yield_stress_of(firsts)
            box%body_hardening = particles%hardening_modulus_of(firsts)
         else
            box%body_yield = spread(box%yield_stress, 1, size(firsts))
            box%body_hardening = spread(box%hardening_modulus, 1, size(firsts))
         end if
      end subroutine body_laws
   end subroutine start_bodies

   !> Kinetic and strain energy and the smallest J of the particles as they are (the variants' start).
   subroutine initial_energies(particles, youngs_modulus, totals)
      type(particles_t), intent(in) :: particles
      real(dp), intent(in) :: youngs_modulus
      type(pass_totals_t), intent(inout) :: totals
      integer :: p
      real(dp) :: m, e, volume0
      totals%kinetic_energy = 0.0_dp
      totals%strain_energy = 0.0_dp
      m = particles%mass
      e = youngs_modulus
      volume0 = particles%volume0
      do p = 1, particles%count
         if (allocated(particles%mass_of)) m = particles%mass_of(p)
         if (allocated(particles%youngs_modulus_of)) e = particles%youngs_modulus_of(p)
         if (allocated(particles%volume0_of)) volume0 = particles%volume0_of(p)
         totals%kinetic_energy = totals%kinetic_energy + 0.5_dp*m*particles%v(p)**2
         totals%strain_energy = totals%strain_energy + 0.5_dp*particles%stress(p)**2*particles%volume_ratio(p)*volume0/e
      end do
      totals%min_volume_ratio = minval(particles%volume_ratio)
   end subroutine initial_energies

   !> One step from time t (the scene's per-particle forces are evaluated at the start of the step they
   !> are mapped for); on entry the element shares hold this step's P2G, on exit the next step's.
   !> USF: nodal velocity -> stress update and its internal force -> momentum update -> G2P fused with
   !> the next mass and momentum shares. USL: momentum update -> one pass of G2P, stress update and the
   !> next P2G. MUSL: momentum update -> G2P with the new momentum mapped back -> nodal velocity ->
   !> stress update fused with the next P2G.
   !> With particles in parts (fused_start's `box`) the nodal sums are reflected at a mirrored fixed
   !> end before they are used (mirror_fold, as on the generic path: the wide shapes' grid has a ghost
   !> cell there). Bodies on stacked fields (`bodies`): the passes on its fields, the contact correction
   !> after each nodal velocity and momentum update (as scheme_step_bodies); the run's grid becomes their sum
   !> when it is read (fused_grid_sum), its lightest node each step. XPIC keeps v^n = p/m of the mapping
   !> (before the force update) and forms v* + dt a after the solve, from which its G2P gathers the
   !> particles' velocity; FMPM filters each nodal velocity the step forms (USF's v^n, the solve's v^L)
   !> before a pass reads it (mpm_xpic, mpm_fmpm: the generic path's order, the same operations).
   subroutine fused_step(scheme, particles, grid, seg, dt, youngs_modulus, totals, box, scene, t, bodies)
      integer, intent(in) :: scheme
      type(particles_t), intent(inout) :: particles
      type(grid_t), intent(inout) :: grid
      !> the run's segments (fused_start planned them)
      type(segments_t), intent(inout) :: seg
      real(dp), intent(in) :: dt, youngs_modulus
      type(pass_totals_t), intent(out) :: totals
      type(fused_box_t), intent(inout), optional :: box
      class(loads_t), intent(in), optional :: scene
      real(dp), intent(in), optional :: t
      type(bodies_t), intent(inout), optional :: bodies
      type(pass_totals_t) :: stress_totals
      logical :: wide, with_box, forced, stacked, mapped, xpic, fmpm
      wide = .false.
      with_box = .false.
      forced = .false.
      stacked = .false.
      mapped = .false.
      xpic = .false.
      fmpm = .false.
      if (present(box)) then
         wide = box%parts
         with_box = allocated(box%carry)
         forced = box%variant == variant_forced
         stacked = on_stacked_fields(box)
         mapped = box%variant == variant_asflip
         xpic = box%variant == variant_xpic
         fmpm = box%fmpm
      end if
      if (stacked) then
         call touch_test(bodies, particles, grid%dx)
         call step_on(bodies%fields)
         ! the run's grid as the bodies' sum only when it is read (fused_grid_sum: a snapshot); the guards
         ! read the lightest node only
         grid%min_node_mass = bodies%fields%min_node_mass
      else
         call step_on(grid)
      end if
   contains
      !> The step on the nodal fields g (the run's grid, or the bodies' stacked fields).
      subroutine step_on(g)
         type(grid_t), intent(inout) :: g
         select case (scheme)
         case (scheme_usf)
            call kinematics(g)
            if (xpic) box%series_field = g%velocity ! v^n
            if (fmpm) call filter(g)
            if (forced) call forces_at(t)
            call pass(g, pass_usf_stress, stress_totals)
            if (mapped) call keep_mapped(g) ! (ASFLIP's v^n, which the stress pass read)
            if (wide) then
               call solve(g)
            else ! the force assembled in the solve (mass and momentum are assembled already)
               call solve_momentum(g, dt, .true.)
               call contact(g, dt)
            end if
            if (mapped) call asflip_separation(g, dt, box%separating)
            call solved(g)
            call pass(g, pass_usf_move, totals)
            call merge_totals(totals, stress_totals)
         case (scheme_usl)
            call solve(g)
            call solved(g)
            if (forced) call forces_at(t + dt)
            if (mapped) call asflip_separation(g, dt, box%separating)
            call pass(g, pass_usl, totals)
         case (scheme_musl)
            call solve(g)
            if (mapped) call asflip_separation(g, dt, box%separating)
            call solved(g)
            call pass(g, pass_musl_remap, totals)
            call kinematics(g)
            if (forced) call forces_at(t + dt)
            call pass(g, pass_musl_stress, stress_totals)
            call merge_totals(totals, stress_totals)
         end select
      end subroutine step_on
      !> Nodal mass and momentum (reflected at a mirrored end: wide shapes), then the nodal velocity
      !> (and the contact correction of bodies).
      subroutine kinematics(g)
         type(grid_t), intent(inout) :: g
         call assemble_nodes(g, .false.)
         if (wide) call mirror_fold(g, .true., .false.)
         call nodal_velocity(g)
         call contact(g, 0.0_dp)
      end subroutine kinematics
      !> Nodal mass, momentum and force (reflected: wide shapes), then the momentum update (and the
      !> contact correction of bodies); the hat's grid has no ghost, and assembles and solves chunk by chunk.
      subroutine solve(g)
         type(grid_t), intent(inout) :: g
         if (wide) then
            call assemble_nodes(g, .true.)
            call mirror_fold(g, .true., .true.)
            call solve_momentum(g, dt, .false.)
         else if (stacked) then
            call assemble_and_solve(g, dt, active_nodes(g, seg, box, bodies))
         else if (mapped) then ! ASFLIP: v^n = p/m of the mapping before the update (the same nodal values)
            call assemble_nodes(g, .true.)
            call nodal_velocity(g)
            call keep_mapped(g)
            call solve_momentum(g, dt, .false.)
         else if (xpic) then ! v^n = p/m between the assembly and the update
            call assemble_nodes(g, .true.)
            box%series_field = g%momentum
            call velocity_of_momentum(g, box%series_field)
            call solve_momentum(g, dt, .false.)
         else
            call assemble_and_solve(g, dt)
         end if
         call contact(g, dt)
      end subroutine solve
      !> For ASFLIP the nodal velocity g%velocity (v^n) becomes box%mapped_velocity, by swapping the arrays (no
      !> copy); the solve then writes v^L over the old one.
      subroutine keep_mapped(g)
         type(grid_t), intent(inout) :: g
         real(dp), allocatable :: swap(:)
         call move_alloc(g%velocity, swap)
         call move_alloc(box%mapped_velocity, g%velocity)
         call move_alloc(swap, box%mapped_velocity)
      end subroutine keep_mapped
      !> After the momentum update: XPIC's field v* + dt a for G2P, FMPM's filtered v^L.
      subroutine solved(g)
         type(grid_t), intent(inout) :: g
         if (xpic) then
            call fused_projection_series(particles, g, box%series_order, box%series_field, box%series_term, &
                                         box%series_projected)
            box%series_field = box%series_field + dt*g%acceleration
         end if
         if (fmpm) call filter(g)
      end subroutine solved
      !> FMPM: the nodal velocity <- v_k of its momentum (the series on M_L^-1 q).
      subroutine filter(g)
         type(grid_t), intent(inout) :: g
         if (box%series_order <= 1) return
         box%series_field = g%velocity
         call fused_projection_series(particles, g, box%series_order, box%series_field, box%series_term, &
                                      box%series_projected)
         g%velocity = box%series_field
      end subroutine filter
      !> Bodies on stacked fields: approaching bodies share their centre-of-mass velocity (mpm_contact).
      subroutine contact(g, step)
         type(grid_t), intent(inout) :: g
         real(dp), intent(in) :: step
         if (stacked) call contact_correct(g, bodies%nodes, bodies%normal, bodies%touching, step, bodies%contact_nodes)
      end subroutine contact
      !> The scene's per-particle forces at time `at` (the variant `forced`).
      subroutine forces_at(at)
         real(dp), intent(in) :: at
         if (forced) call scene%particle_forces(at, particles, box%forces)
      end subroutine forces_at
      !> One fused pass, with the particles' parts (or variant) when they have some.
      subroutine pass(g, kind, pass_totals)
         type(grid_t), intent(inout) :: g
         integer, intent(in) :: kind
         type(pass_totals_t), intent(out) :: pass_totals
         if (with_box) then
            call fused_pass(kind, particles, g, seg, dt, youngs_modulus, pass_totals, box)
         else
            call fused_pass(kind, particles, g, seg, dt, youngs_modulus, pass_totals)
         end if
      end subroutine pass
   end subroutine fused_step

   !> Bodies on stacked fields: the nodes each body's grid half of a step must assemble and solve (columns
   !> first, last per body), and bodies%active for the next step. A body's passes wrote its element
   !> shares on the elements segments_t%written says (the others hold zeros: the passes clear what they
   !> wrote), so its nodes of those elements, and the nodes it held values at after the last step (zero
   !> now if they are not among them); every other node of its field holds zeros and would stay so. Each
   !> body's field spans the whole grid, the body only its part: solving every node was a quarter of a
   !> frictionless impact's time at 1e4 particles.
   function active_nodes(g, seg, box, bodies) result(ranges)
      type(grid_t), intent(in) :: g
      type(segments_t), intent(in) :: seg
      type(fused_box_t), intent(in) :: box
      type(bodies_t), intent(inout) :: bodies
      integer :: ranges(2, bodies%count)
      integer :: now(2, bodies%count)
      integer :: k, b, kind
      now(1, :) = huge(1)
      now(2, :) = -huge(1)
      if (.not. seg%clear_written) then ! (no record of what was written: every node)
         do b = 1, bodies%count
            now(:, b) = [(b - 1)*bodies%nodes, b*bodies%nodes - 1]
         end do
      end if
      do k = 1, seg%count
         b = body_of_element(box, seg%first_element(k))
         do kind = 1, size(seg%written, 2)
            ! (the kinds of share the fields have: no forces, no record of them but the first "whole")
            if (kind == size(seg%written, 2) .and. .not. allocated(g%element_force_left)) cycle
            if (seg%written(1, kind, k) > seg%written(2, kind, k)) cycle ! (none)
            now(1, b) = min(now(1, b), seg%written(1, kind, k) - 1)
            now(2, b) = max(now(2, b), seg%written(2, kind, k))
         end do
      end do
      ranges(1, :) = min(now(1, :), bodies%active(1, :))
      ranges(2, :) = max(now(2, :), bodies%active(2, :))
      bodies%active = now
   end function active_nodes

   !> After a step of bodies on stacked fields: the run's grid as their sum (mass, momentum, force, velocity;
   !> fused_step leaves it as it was, for nothing but a snapshot reads it). Nothing for other runs.
   subroutine fused_grid_sum(grid, box, bodies)
      type(grid_t), intent(inout) :: grid
      type(fused_box_t), intent(in) :: box
      type(bodies_t), intent(in) :: bodies
      if (on_stacked_fields(box)) call combine_bodies(bodies, grid)
   end subroutine fused_grid_sum

   !> Whether the run's bodies are on stacked fields (a velocity field each; the variant `bodies` with
   !> more than one body's field), once start_bodies has described them.
   pure logical function on_stacked_fields(box)
      type(fused_box_t), intent(in) :: box
      on_stacked_fields = .false.
      if (box%variant == variant_bodies) on_stacked_fields = size(box%body_element) > 1
   end function on_stacked_fields

   !> The nodal velocity p_I / m_I of the mapping the element shares hold (the run's grid; bodies on
   !> stacked fields: each body's, then their sum on the run's grid), reflected at a mirrored end.
   subroutine fused_grid_velocity(grid, box, bodies)
      type(grid_t), intent(inout) :: grid
      type(fused_box_t), intent(in) :: box
      type(bodies_t), intent(inout) :: bodies
      if (on_stacked_fields(box)) then
         call assemble_nodes(bodies%fields, .false.)
         call nodal_velocity(bodies%fields)
         call combine_bodies(bodies, grid)
         return
      end if
      call assemble_nodes(grid, .false.)
      call mirror_fold(grid, .true., .false.)
      call nodal_velocity(grid)
   end subroutine fused_grid_velocity

   !> The fused kernels' description of shape `kind` (mpm_shape's ids): the hat, or a particle in parts
   !> (GIMP's box, fixed or stretched; the B-splines, in two parts or, cubic, three).
   pure function fused_shape(kind) result(box)
      integer, intent(in) :: kind
      type(fused_box_t) :: box
      box%parts = kind /= shape_linear
      box%stretch = kind == shape_cpgimp
      box%spline = kind == shape_bspline2 .or. kind == shape_bspline3
      box%cubic = kind == shape_bspline3
   end function fused_shape


   !> What the fused kernels carry from one step to the next beyond the run's grid: the segments' record
   !> of the last pass, and the bodies' fields of a contact run.
   subroutine fused_sync_state(self, state)
      class(fused_stepper_t), intent(inout) :: self
      type(state_t), intent(inout) :: state
      call sync_segments(state, 'fused.segments', self%segments)
      if (self%contact) call sync_bodies(state, self%bodies)
   end subroutine fused_sync_state
end module mpm_fused
