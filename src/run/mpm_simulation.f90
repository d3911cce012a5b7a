!> One run: set up the scene, step the chosen scheme, record diagnostics, watch the guards.
!> No file output here (see mpm_output); safe to call from several threads at once.
module mpm_simulation
   use, intrinsic :: ieee_arithmetic, only: ieee_is_finite, ieee_value, ieee_quiet_nan
   use omp_lib, only: omp_get_wtime
   use mpm_kinds, only: dp
   use mpm_errors, only: error_t, set_error
   use mpm_strings, only: str, plural
   use mpm_config, only: config_t, material_of, periodic_snapshots
   use mpm_material, only: material_t, material_state, material_report
   use mpm_grid, only: grid_t, grid_init, sync_grid
   use mpm_particles, only: particles_t, per_particle_data, sync_particles
   use mpm_state, only: state_t
   use mpm_shape, only: shape_cache_t, shape_id, shape_extra_cells, shape_support, transfer_id, transfer_apic, &
                        transfer_xpic, transfer_fmpm, transfer_asflip, shape_cpdi, formulation_id, formulation_total
   use mpm_shape_cpdi, only: cpdi_corners
   use mpm_stepper, only: stepper_t, stepper_stop_t, scheme_id
   use mpm_fused, only: fused_box_t, fused_choose, fused_stepper_t
   use mpm_schemes, only: generic_stepper_t
   use mpm_fused_cpdi, only: cpdi_stepper_t, cpdi_fast
   use mpm_scene, only: scene_t, watch_t
   use mpm_diagnostics, only: history_t, snapshot_t, status_ok, status_non_finite, status_volume_ratio, &
                              status_left_grid, status_energy_growth, status_cell_crossing, status_name, &
                              status_not_run, status_newton, status_domain_stretched, exact_name_length
   use mpm_pass_totals, only: pass_totals_t
   use mpm_files, only: interrupt_signal
   use mpm_implicit, only: implicit_stepper_t, implicit_init, integrator_id, integrator_explicit
   implicit none
   private
   public :: run_result_t, run_simulation, guard_trip_t, guard_message, checkpoint_sink_t

   !> Where a run puts its checkpoints (mpm_checkpoint writes them to a file): `save` gets the run's
   !> whole state after every `every` steps (0: never) but the last, and after the step a signal stopped
   !> it at (the run goes on when a save fails: the sink keeps why).
   type, abstract :: checkpoint_sink_t
      integer :: every = 0
   contains
      procedure(save_i), deferred :: save
   end type checkpoint_sink_t

   abstract interface
      subroutine save_i(self, state, step)
         import :: checkpoint_sink_t, state_t
         class(checkpoint_sink_t), intent(inout) :: self
         type(state_t), intent(in) :: state
         integer, intent(in) :: step
      end subroutine save_i
   end interface

   !> A node lighter than this fraction of a particle's mass is "nearly empty" in guard messages.
   real(dp), parameter :: nearly_empty = 0.01_dp

   !> What a guard saw when it stopped a run. Numbers only: the text is made by `guard_message`
   !> outside any parallel region (gfortran's formatted internal writes are not safe to run
   !> concurrently: messages built in sweep threads came out garbled).
   type :: guard_trip_t
      integer :: step = 0
      integer :: particle = 0       !< the particle at fault (0 if none)
      real(dp) :: time = 0.0_dp
      real(dp) :: value = 0.0_dp    !< the quantity that tripped (energy ratio, cells moved)
      real(dp) :: x = 0.0_dp, v = 0.0_dp, stress = 0.0_dp, volume_ratio = 0.0_dp
      real(dp) :: domain(2) = 0.0_dp  !< the grid domain [x_min, x_max] (m), for left_grid
      real(dp) :: node_mass_ratio = 0.0_dp  !< the lightest nodal mass of the step / particle mass
      integer :: iteration = 0      !< newton_not_converged: the linear solves made
      integer :: node = -1          !< newton_not_converged: the node of a singular tangent (-1: none)
      logical :: mass_matrix = .false.  !< newton_not_converged: the singular matrix was the consistent mass
   end type guard_trip_t

   !> What one run produced.
   type :: run_result_t
      integer :: status = status_ok
      type(guard_trip_t) :: trip            !< when status /= ok
      integer :: steps = 0          !< steps asked for
      integer :: steps_done = 0     !< steps completed (= steps unless a guard tripped)
      real(dp) :: dt = 0.0_dp
      !> max over recorded steps of the scene's error measure (the bar's: |u_cm - u_cm,exact| in m)
      real(dp) :: max_error = 0.0_dp
      real(dp) :: relative_error = 0.0_dp   !< max_error / the scene's amplitude (ucm_amplitude)
      real(dp) :: ucm_amplitude = 0.0_dp    !< the scene's amplitude (m): the bar's exact u_cm amplitude
      character(len=:), allocatable :: error_name  !< what max_error measures (the scene's error_name)
      character(len=:), allocatable :: error_unit  !< its unit (m unless the scene says otherwise)
      !> What the scene reports in /summary beyond the common quantities (names and values).
      character(len=32), allocatable :: report_names(:)
      real(dp), allocatable :: report_values(:)
      real(dp) :: run_time = 0.0_dp         !< set-up and time loop, seconds (no file output)
      !> the time loop alone, seconds of processor time (of all threads; the steps' cost without the set-up),
      !> when run_simulation was asked for it (processor_time); NaN otherwise
      real(dp) :: loop_cpu_time = 0.0_dp
      real(dp) :: initial_energy = 0.0_dp   !< kinetic + strain energy at t = 0 (J per unit area)
      real(dp) :: final_energy = 0.0_dp
      real(dp) :: max_energy_ratio = 0.0_dp !< largest (kinetic + strain) / initial energy reached
      real(dp) :: min_volume_ratio = 1.0_dp !< smallest J met
      real(dp) :: max_cell_move = 0.0_dp    !< largest particle move in one step, in cells
      real(dp) :: min_node_mass_ratio = 0.0_dp !< smallest nodal mass / particle mass met
      integer :: particles = 0
      real(dp) :: domain(2) = 0.0_dp        !< the grid domain [x_min, x_max] (m)
      logical :: fused = .false.            !< whether a fast path ran (the fused kernels, CPDI's lean step; else the generic path)
      type(history_t) :: history
      type(snapshot_t), allocatable :: snapshots(:)
   end type run_result_t

   !> Everything one run steps: the scene, its particles and grid, the stepper chosen for it, and the
   !> running quantities the guards and the result read.
   type :: run_state_t
      class(scene_t), allocatable :: scene
      type(grid_t) :: grid
      type(particles_t) :: particles
      type(pass_totals_t) :: totals
      !> how the run steps (mpm_stepper: the generic path, the fused kernels, an implicit integrator)
      class(stepper_t), allocatable :: stepper
      type(material_t) :: material        !< the law and its parameters (mpm_material)
      class(watch_t), allocatable :: watch  !< what a watching scene keeps between steps
      !> the next of the configuration's snapshot times, and the snapshots taken so far
      integer :: next_snapshot = 1, snapshots_taken = 0
      logical :: fused = .false.          !< the fused kernels run (else the generic path)
      real(dp) :: total_mass = 0.0_dp, energy_reference = 0.0_dp
      real(dp) :: ucm = 0.0_dp, energy = 0.0_dp  !< u_cm and the total energy after the last step
   end type run_state_t

contains

   !> Run the validated and resolved `config`. Guard trips end the run with result%status /= 0 and
   !> the state reached so far; `error` is set only when the run cannot be set up (memory).
   !> `record_history` keeps one history entry per step; snapshots are taken when the configuration asks.
   !> A signal caught by a sweep (mpm_files, catch_interrupts) ends the run at its next step with
   !> status_not_run: the run was abandoned, its numbers are no result.
   subroutine run_simulation(config, result, error, record_history, checkpoints, restart, processor_time)
      type(config_t), intent(in) :: config
      type(run_result_t), intent(out) :: result
      type(error_t), allocatable, intent(out) :: error
      logical, intent(in) :: record_history
      !> where the run's checkpoints go (none when absent or every = 0)
      class(checkpoint_sink_t), intent(inout), optional :: checkpoints
      !> the state a checkpoint of this run kept: the run continues from it, to the file the
      !> uninterrupted run gives (bit for bit); `error` when it lacks a value (a damaged checkpoint)
      type(state_t), intent(inout), optional :: restart
      !> measure the time loop's processor time (result%loop_cpu_time): two system calls, which a sweep
      !> of small cases would pay at every case for a number it does not report
      logical, intent(in), optional :: processor_time
      type(run_state_t) :: run
      type(state_t) :: state
      real(dp) :: start, loop_start, loop_end
      integer :: n, first, every
      logical :: clocked

      start = omp_get_wtime()
      every = 0
      if (present(checkpoints)) every = checkpoints%every
      call set_up(config, run, result, error)
      if (allocated(error)) return
      call first_state(config, run, result, record_history)
      first = 1
      if (present(restart)) then
         call restore(restart, run, result, first, error)
         if (allocated(error)) return
      end if
      clocked = .false.
      if (present(processor_time)) clocked = processor_time
      if (clocked) call cpu_time(loop_start)
      do n = first, config%steps
         call advance(config, run, result, n, record_history)
         call check_guards(config, run, result, n, n*config%dt)
         if (result%status /= status_ok) exit
         result%steps_done = n
         call take_snapshots(config, run, result, n, n*config%dt)
         if (interrupt_signal() /= 0) then
            result%status = status_not_run
            if (every > 0) then ! (the step it reached: --restart continues from there)
               call capture(run, result, n, state)
               call checkpoints%save(state, n)
            end if
            exit
         end if
         if (every > 0 .and. n < config%steps) then
            if (mod(n, every) == 0) then
               call capture(run, result, n, state)
               call checkpoints%save(state, n)
            end if
         end if
      end do
      if (clocked) then
         call cpu_time(loop_end)
         result%loop_cpu_time = loop_end - loop_start
      else
         result%loop_cpu_time = ieee_value(0.0_dp, ieee_quiet_nan)
      end if
      call finish(config, run, result)
      result%run_time = omp_get_wtime() - start
   end subroutine run_simulation

   !> The scene, its particles and grid, the stepper (fused kernels, generic path or implicit) and what
   !> the result reports before the first step.
   subroutine set_up(config, run, result, error)
      type(config_t), intent(in) :: config
      type(run_state_t), intent(inout) :: run
      type(run_result_t), intent(inout) :: result
      type(error_t), allocatable, intent(out) :: error
      type(fused_box_t) :: box
      integer :: extra, stat, kind, transfer, integrator, margin, ghost
      result%steps = config%steps
      result%dt = config%dt
      integrator = integrator_id(config%integrator)
      run%material = material_of(config)
      call config%scene%make(config, run%scene, error)
      if (allocated(error)) return
      associate (scene => run%scene, particles => run%particles)
         kind = shape_id(config%shape)
         transfer = transfer_id(config%transfer)
         ! shapes wider than the hat: one more cell beyond the free end, one ghost cell left of x = 0
         extra = shape_extra_cells(kind)
         result%ucm_amplitude = scene%ucm_amplitude()
         result%error_name = scene%error_name()
         result%error_unit = scene%error_unit()
         call scene%report(result%report_names, result%report_values)
         call scene%place_particles(config, particles, error)
         if (allocated(error)) return
         ! the fused kernels, where they take the scene, shape, transfer, law and what the particles carry;
         ! they are explicit
         box = fused_choose(kind, transfer, config%flip_fraction, scene%fused_applies(), scene%body_fields, scene, &
                           particles, run%material, formulation_id(config%formulation) == formulation_total, &
                           scheme_id(config%scheme))
         box%move_guard = config%max_cell_move ! (check_guards names the particle only beyond it)
         run%fused = trim(config%kernels) == 'auto' .and. box%variant >= 0 .and. integrator == integrator_explicit
         result%fused = run%fused
         if (.not. run%fused) call per_particle_data(particles, error)
         if (allocated(error)) return
         call material_state(run%material, particles, error)
         if (allocated(error)) return
         if (transfer == transfer_apic) then
            ! APIC starts from C_p = 0 (the first P2G is PIC's)
            allocate (particles%velocity_gradient(particles%count), stat=stat)
            if (stat /= 0) then
               call set_error(error, 'cannot allocate the APIC velocity gradients (out of memory)')
               return
            end if
            particles%velocity_gradient = 0.0_dp
         end if
         margin = scene%margin_cells(config%dx, config%margin_cells) + extra
         ghost = extra + scene%left_margin_cells(config%dx, config%margin_cells)
         ! every node a particle's support columns name must exist: a grid of at least support - 1 cells
         ! (CPDI's four columns on a body of one or two elements between fixed ends: empty cells beyond
         ! its right end, which no particle's weights reach)
         margin = margin + max(0, shape_support(kind) - 1 - (config%elements + ghost + margin))
         call grid_init(run%grid, config%elements, config%length, particles%mass, error, margin=margin, &
                        fixed=scene%fixed_nodes(), element_shares=run%fused, ghost=ghost)
         if (allocated(error)) return
         call choose_stepper(config, run, box, integrator, kind, transfer, error)
         select type (stepper => run%stepper)
         type is (cpdi_stepper_t)
            result%fused = .true.
         end select
         if (allocated(error)) return
         result%domain = [run%grid%origin, run%grid%origin + run%grid%length]
         result%particles = particles%count
      end associate
   end subroutine set_up

   !> The run's stepper, chosen once: the fused kernels (run%fused, described by `box`), an implicit
   !> integrator, CPDI's lean step where it applies (mpm_fused_cpdi's cpdi_fast; kernels = 'auto'), or the
   !> explicit schemes on the generic operations; with the scene's velocity field per body where it has one.
   subroutine choose_stepper(config, run, box, integrator, kind, transfer, error)
      type(config_t), intent(in) :: config
      type(run_state_t), intent(inout) :: run
      type(fused_box_t), intent(in) :: box
      integer, intent(in) :: integrator, kind, transfer
      type(error_t), allocatable, intent(out) :: error
      ! (made in place: a copy would hold a large run's contact fields twice)
      if (run%fused) then
         allocate (fused_stepper_t :: run%stepper)
      else if (integrator /= integrator_explicit) then ! Newton on the grid (mpm_implicit)
         allocate (implicit_stepper_t :: run%stepper)
      else if (kind == shape_cpdi .and. trim(config%kernels) == 'auto' .and. &
               cpdi_fast(scheme_id(config%scheme), transfer, formulation_id(config%formulation) == formulation_total, &
                         run%particles, run%scene)) then
         allocate (cpdi_stepper_t :: run%stepper)
      else
         allocate (generic_stepper_t :: run%stepper)
      end if
      run%stepper%scheme = scheme_id(config%scheme)
      select type (stepper => run%stepper)
      type is (fused_stepper_t)
         stepper%box = box
         stepper%box%asflip_alpha = config%asflip_alpha
         if (transfer == transfer_xpic) stepper%box%series_order = config%xpic_order
         if (transfer == transfer_fmpm) stepper%box%series_order = config%fmpm_order
         stepper%youngs_modulus = config%youngs_modulus
         stepper%contact = run%scene%body_fields
         call stepper%attach(run%grid, run%particles, error)
      class is (generic_stepper_t) ! (and its extension, the implicit integrators')
         stepper%cache%kind = kind
         stepper%cache%transfer = transfer
         stepper%cache%flip_fraction = config%flip_fraction
         if (transfer == transfer_xpic) stepper%cache%order = config%xpic_order
         if (transfer == transfer_fmpm) stepper%cache%order = config%fmpm_order
         if (transfer == transfer_asflip) stepper%cache%alpha = config%asflip_alpha
         stepper%cache%total = formulation_id(config%formulation) == formulation_total
         if (kind == shape_cpdi) call corners(stepper%cache) ! each particle's sub-cell, tiling each body
         stepper%material = run%material
         stepper%contact = run%scene%body_fields
         select type (stepper)
         type is (implicit_stepper_t)
            call implicit_init(stepper%im, config)
         end select
         call stepper%attach(run%grid, run%particles, error)
      end select
   contains
      !> CPDI's domains: their corners at the particles' reference positions, one chain per body.
      subroutine corners(cache)
         type(shape_cache_t), intent(inout) :: cache
         associate (particles => run%particles, grid => run%grid)
            if (allocated(particles%body)) then
               call cpdi_corners(particles%x0, particles%volume0_of, grid%origin, grid%origin + grid%length, &
                                 cache%corners, cache%corner_of, particles%body)
            else
               call cpdi_corners(particles%x0, particles%volume0_of, grid%origin, grid%origin + grid%length, &
                                 cache%corners, cache%corner_of)
            end if
         end associate
      end subroutine corners
   end subroutine choose_stepper

   !> The state at t = 0: the first mapping, the energies the guards compare with, the first history
   !> entry and the snapshots at t = 0.
   subroutine first_state(config, run, result, record_history)
      type(config_t), intent(in) :: config
      type(run_state_t), intent(inout) :: run
      type(run_result_t), intent(inout) :: result
      logical, intent(in) :: record_history
      call run%stepper%start(run%scene, run%particles, run%grid, run%totals)
      run%total_mass = run%stepper%displacement_mass(run%particles)
      call finite_energies(run%particles, config%youngs_modulus, run%totals)
      result%initial_energy = run%totals%kinetic_energy + run%totals%strain_energy + run%totals%plastic_work
      ! Zero initial energy (v0 = 0) stays exactly zero in a sound run: any growth trips the guard.
      run%energy_reference = run%scene%energy_reference(result%initial_energy)
      result%final_energy = result%initial_energy
      result%max_energy_ratio = result%initial_energy/run%energy_reference
      result%min_volume_ratio = run%totals%min_volume_ratio
      result%min_node_mass_ratio = huge(1.0_dp)
      run%ucm = 0.0_dp
      if (record_history) call start_history(result%history, config%steps, allocated(run%particles%hardening))
      if (record_history) call record(result%history, 0.0_dp, run%ucm, 0.0_dp, run%totals)
      run%next_snapshot = 1
      run%snapshots_taken = 0
      allocate (result%snapshots(config%snapshot_count + periodic_snapshots(config%snapshot_every, config%steps)))
      call take_snapshots(config, run, result, 0, 0.0_dp)
   end subroutine first_state

   !> Step `n`: the scheme's update from t = (n - 1) dt to n dt, then what the run records of it.
   subroutine advance(config, run, result, n, record_history)
      type(config_t), intent(in) :: config
      type(run_state_t), intent(inout) :: run
      type(run_result_t), intent(inout) :: result
      integer, intent(in) :: n
      logical, intent(in) :: record_history
      real(dp) :: t, exact, error
      associate (particles => run%particles, grid => run%grid, totals => run%totals)
         t = (n - 1)*config%dt
         call run%stepper%step(run%scene, particles, grid, config%dt, t, totals)
         ! u_cm = sum m (x - X) / sum m (equal masses on the fused kernels: sum (x - X) / N)
         run%ucm = totals%displacement/run%total_mass
         t = n*config%dt
         if (record_history) exact = run%scene%ucm_exact(t)  ! (error_at evaluates it too: once a step without history)
         call finite_energies(particles, config%youngs_modulus, totals)
         run%energy = totals%kinetic_energy + totals%strain_energy + totals%plastic_work ! (0 for elastic laws)
         if (run%scene%watches) then ! (the scene's watch gives the error measure too)
            call run%scene%watch_step(t, particles, totals, run%ucm, run%watch, error)
         else
            error = run%scene%error_at(t, particles, run%ucm)
         end if
         result%max_error = max(result%max_error, error)
         result%final_energy = run%energy
         result%max_energy_ratio = max(result%max_energy_ratio, run%energy/run%energy_reference)
         result%min_volume_ratio = min(result%min_volume_ratio, totals%min_volume_ratio)
         result%max_cell_move = max(result%max_cell_move, totals%max_cell_move)
         result%min_node_mass_ratio = min(result%min_node_mass_ratio, grid%min_node_mass/particles%mass)
         if (record_history) call record(result%history, t, run%ucm, exact, totals)
      end associate
   end subroutine advance

   !> After the last step: what the scene watched, the relative error, and the rule that a completed
   !> run reports no non-finite number.
   subroutine finish(config, run, result)
      type(config_t), intent(in) :: config
      type(run_state_t), intent(inout) :: run
      type(run_result_t), intent(inout) :: result
      character(len=32), allocatable :: names(:)
      real(dp), allocatable :: values(:)
      if (run%scene%watches) then
         call run%scene%watch_report(run%watch, run%particles, names, values)
         call add_report(result, names, values)
      end if
      call material_report(run%material, run%particles, names, values) ! (none for elastic laws)
      call add_report(result, names, values)
      call run%stepper%report(names, values) ! (the implicit integrators' Newton statistics)
      call add_report(result, names, values)
      if (result%ucm_amplitude /= 0.0_dp) then
         result%relative_error = result%max_error/abs(result%ucm_amplitude)
      else
         result%relative_error = result%max_error
      end if
      ! a completed run never reports a non-finite number: if an exact solution or error measure overflowed
      ! although the particle state stayed finite, the run counts as stopped by the non-finite guard
      if (result%status == status_ok .and. .not. all(ieee_is_finite([result%max_error, result%relative_error, &
          result%ucm_amplitude, result%initial_energy, result%final_energy, result%max_energy_ratio]))) &
         call trip(run, result, config%steps, config%steps*config%dt, status_non_finite, result%max_energy_ratio, &
                   first_non_finite(run%particles))
   end subroutine finish

   !> Trip the first guard that applies, in order of severity, and record the culprit.
   subroutine check_guards(config, run, result, step, time)
      type(config_t), intent(in) :: config
      type(run_state_t), intent(in) :: run
      type(run_result_t), intent(inout) :: result
      integer, intent(in) :: step
      real(dp), intent(in) :: time
      type(stepper_stop_t) :: halt
      halt = run%stepper%stop_reason()
      associate (energy => run%energy, totals => run%totals, particles => run%particles, &
                 reference => run%energy_reference)
         if (halt%stopped) then
            call trip(run, result, step, time, status_newton, halt%residual, 0)
            result%trip%iteration = halt%iteration
            result%trip%node = halt%node
            result%trip%mass_matrix = halt%mass_matrix
         else if (.not. ieee_is_finite(energy) .or. .not. ieee_is_finite(run%ucm)) then
            call trip(run, result, step, time, status_non_finite, energy/reference, first_non_finite(particles))
         else if (totals%outside /= 0) then
            call trip(run, result, step, time, status_left_grid, 0.0_dp, totals%outside)
         else if (halt%stretched /= 0) then
            call trip(run, result, step, time, status_domain_stretched, 0.0_dp, halt%stretched)
         else if (totals%min_volume_ratio <= 0.0_dp) then
            call trip(run, result, step, time, status_volume_ratio, totals%min_volume_ratio, &
                      minloc(particles%volume_ratio, 1))
         else if (totals%max_cell_move > config%max_cell_move) then
            call trip(run, result, step, time, status_cell_crossing, totals%max_cell_move, totals%furthest)
         else if (energy > config%energy_growth_limit*reference) then
            call trip(run, result, step, time, status_energy_growth, energy/reference, maxloc(abs(particles%v), 1))
         end if
      end associate
   end subroutine check_guards

   subroutine trip(run, result, step, time, code, value, p)
      type(run_state_t), intent(in) :: run
      type(run_result_t), intent(inout) :: result
      integer, intent(in) :: step, code, p
      real(dp), intent(in) :: time, value
      result%status = code
      result%trip%step = step
      result%trip%time = time
      result%trip%value = value
      result%trip%particle = p
      result%trip%domain = result%domain
      result%trip%node_mass_ratio = run%grid%min_node_mass/run%particles%mass
      if (p >= 1 .and. p <= run%particles%count) then
         result%trip%x = run%particles%x(p)
         result%trip%v = run%particles%v(p)
         result%trip%stress = run%particles%stress(p)
         result%trip%volume_ratio = run%particles%volume_ratio(p)
      end if
   end subroutine trip

   !> The snapshots due at `step`: one per snapshot time reached (in order), and one every snapshot_every
   !> steps unless a snapshot time gave the step one already.
   subroutine take_snapshots(config, run, result, step, time)
      type(config_t), intent(in) :: config
      type(run_state_t), intent(inout) :: run
      type(run_result_t), intent(inout) :: result
      integer, intent(in) :: step
      real(dp), intent(in) :: time
      logical :: periodic
      periodic = config%snapshot_every > 0
      if (periodic) periodic = mod(step, config%snapshot_every) == 0
      do while (run%next_snapshot <= config%snapshot_count)
         if (config%snapshot_times(run%next_snapshot) > time + 0.5_dp*config%dt) exit
         call take_snapshot(run, result, step, time)
         run%next_snapshot = run%next_snapshot + 1
         periodic = .false.
      end do
      if (periodic) call take_snapshot(run, result, step, time)
   end subroutine take_snapshots

   !> The particle and grid state into the next free snapshot of `result`.
   subroutine take_snapshot(run, result, step, time)
      type(run_state_t), intent(inout) :: run
      type(run_result_t), intent(inout) :: result
      integer, intent(in) :: step
      real(dp), intent(in) :: time
      integer :: i
      call run%stepper%snapshot_grid(run%particles, run%grid, step)
      run%snapshots_taken = run%snapshots_taken + 1
      associate (s => result%snapshots(run%snapshots_taken), particles => run%particles, grid => run%grid)
         s%time = time
         s%step = step
         s%x = particles%x
         s%x0 = particles%x0
         if (allocated(particles%youngs_modulus_of)) s%youngs_modulus = particles%youngs_modulus_of
         if (allocated(particles%body)) s%body = particles%body
         s%v = particles%v
         s%stress = particles%stress
         s%volume_ratio = particles%volume_ratio
         if (allocated(particles%plastic_strain)) s%plastic_strain = particles%plastic_strain
         s%grid_x = [(grid%origin + i*grid%dx, i=0, grid%elements)]
         s%grid_velocity = grid%velocity
         call run%scene%exact_fields(particles%x0, time, s%exact_names, s%exact)
      end associate
   end subroutine take_snapshot

   !> The message of a run stopped by a guard: what tripped, when, and the particle at fault.
   !> Call it outside parallel regions (it uses formatted internal writes).
   function guard_message(status, trip, config) result(text)
      integer, intent(in) :: status
      type(guard_trip_t), intent(in) :: trip
      type(config_t), intent(in) :: config
      character(len=:), allocatable :: text, what
      select case (status)
      case (status_non_finite)
         if (trip%particle > 0) then
            what = 'non-finite value (NaN or Infinity) in the particle state'
         else
            what = 'non-finite value (NaN or Infinity) in the exact solution, the error or the energies (the '// &
                   'particle state is finite): the scene cannot be represented at this scale'
         end if
      case (status_newton)
         if (trip%mass_matrix) then
            what = 'the consistent mass matrix is singular (its LU factorisation: a zero pivot at node '// &
                   str(trip%node)//'): M_IJ = sum_p m_p N_Ip N_Jp has rank at most the number of particles, and '// &
                   'with '//plural(config%particles_per_element, 'particle')//' per element a free end or a '// &
                   'particle entering a new cell leaves it short of the nodes it spans; allowed: '// &
                   'particles_per_element >= 2, or mass = ''lumped'''
         else if (trip%node >= 0) then
            what = 'the tangent is singular (its LU factorisation: a zero pivot at node '//str(trip%node)//') at Newton '// &
                   'iteration '//str(trip%iteration + 1)
         else
            what = 'Newton''s method did not converge: relative residual '//str(trip%value)//' after '// &
                   str(trip%iteration)//' linear solves (newton_tolerance = '//str(config%newton_tolerance)// &
                   ', max_newton_iterations = '//str(config%max_newton_iterations)//')'
         end if
      case (status_left_grid)
         what = 'a particle left the grid domain ['//str(trip%domain(1))//', '//str(trip%domain(2))// &
                '] m (the body with its margin_cells; a larger margin_cells widens it)'
      case (status_volume_ratio)
         what = 'volume ratio J = V/V0 <= 0'
      case (status_domain_stretched)
         what = 'a CPDI particle domain stretched over more than the four nodes a CPDI particle touches (its '// &
                'corners lie in cells more than two apart); more particles per element shorten the domains'
      case (status_cell_crossing)
         what = 'a particle moved '//str(trip%value)//' cells in one step (limit '//str(config%max_cell_move)//')'
      case (status_energy_growth)
         what = 'total energy grew to '//str(trip%value)//' times its initial value (limit '// &
                str(config%energy_growth_limit)//')'
         if (trip%node_mass_ratio < nearly_empty) what = what//'; the lightest node holds '// &
            str(trip%node_mass_ratio)//' of a particle''s mass: a particle has just entered an empty cell, and '// &
            'that node''s velocity drives the update (the cell-crossing instability of linear shape functions, '// &
            'strongest in USL; see docs/user-guide.md, Guards)'
      case default
         text = status_name(status)
         return
      end select
      text = 'guard '//status_name(status)//' tripped at step '//str(trip%step)//' of '//str(config%steps)// &
             ' (t = '//str(trip%time)//' s, dt = '//str(config%dt)//' s): '//what
      if (trip%particle > 0) text = text//'; particle '//str(trip%particle)//': x = '//str(trip%x)//' m, v = '// &
                                    str(trip%v)//' m/s, stress = '//str(trip%stress)//' Pa, J = '//str(trip%volume_ratio)
   end function guard_message

   !> The kernels sum energies as m v^2 / 2 and sigma^2 J V0 / 2E, whose products overflow before the
   !> energy does when E or v is near the largest double (E = 1e308: sigma^2 ~ 1e309 while the strain
   !> energy is ~ 1e-2 J/m^2). When a sum is not finite but the particle state is, both are computed
   !> again from the state in scaled form, (sqrt(m) v)^2 / 2 and (sigma sqrt(J V0 / E))^2 / 2, which
   !> overflow only when the energy itself does. Finite sums are left as they are (same bits as before).
   subroutine finite_energies(particles, youngs_modulus, totals)
      type(particles_t), intent(in) :: particles
      real(dp), intent(in) :: youngs_modulus
      type(pass_totals_t), intent(inout) :: totals
      real(dp) :: kinetic, strain, m, v0, e
      integer :: p
      if (ieee_is_finite(totals%kinetic_energy) .and. ieee_is_finite(totals%strain_energy)) return
      if (first_non_finite(particles) /= 0) return ! the state itself: the non-finite guard trips
      kinetic = 0.0_dp
      strain = 0.0_dp
      do p = 1, particles%count
         m = particles%mass
         v0 = particles%volume0
         e = youngs_modulus
         if (allocated(particles%mass_of)) m = particles%mass_of(p)
         if (allocated(particles%volume0_of)) v0 = particles%volume0_of(p)
         if (allocated(particles%youngs_modulus_of)) e = particles%youngs_modulus_of(p)
         kinetic = kinetic + 0.5_dp*(sqrt(m)*particles%v(p))**2
         strain = strain + 0.5_dp*(particles%stress(p)*sqrt(particles%volume_ratio(p)*v0/e))**2
      end do
      totals%kinetic_energy = kinetic
      totals%strain_energy = strain
   end subroutine finite_energies

   integer function first_non_finite(particles) result(p)
      type(particles_t), intent(in) :: particles
      do p = 1, particles%count
         if (.not. (ieee_is_finite(particles%x(p)) .and. ieee_is_finite(particles%v(p)) .and. &
                    ieee_is_finite(particles%stress(p)) .and. ieee_is_finite(particles%volume_ratio(p)))) return
      end do
      p = 0
   end function first_non_finite

   subroutine start_history(history, steps, plastic)
      type(history_t), intent(out) :: history
      integer, intent(in) :: steps
      logical, intent(in) :: plastic  !< a body is elastoplastic: keep the plastic work too
      allocate (history%time(0:steps), history%ucm(0:steps), history%ucm_exact(0:steps), &
                history%kinetic_energy(0:steps), history%strain_energy(0:steps))
      if (plastic) allocate (history%plastic_work(0:steps))
      history%recorded = 0
   end subroutine start_history

   subroutine record(history, t, ucm, exact, totals)
      type(history_t), intent(inout) :: history
      real(dp), intent(in) :: t, ucm, exact
      type(pass_totals_t), intent(in) :: totals
      integer :: i
      i = history%recorded
      history%time(i) = t
      history%ucm(i) = ucm
      history%ucm_exact(i) = exact
      history%kinetic_energy(i) = totals%kinetic_energy
      history%strain_energy(i) = totals%strain_energy
      if (allocated(history%plastic_work)) history%plastic_work(i) = totals%plastic_work
      history%recorded = i + 1
   end subroutine record

   !> Append to the run's /summary quantities (element by element: gfortran 12 gave an array constructor
   !> of an empty and a non-empty character array the wrong length, and corrupted the heap).
   subroutine add_report(result, names, values)
      type(run_result_t), intent(inout) :: result
      character(len=32), intent(in) :: names(:)
      real(dp), intent(in) :: values(:)
      character(len=32), allocatable :: all_names(:)
      real(dp), allocatable :: all_values(:)
      integer :: n
      n = size(result%report_names)
      allocate (all_names(n + size(names)), all_values(n + size(names)))
      all_names(1:n) = result%report_names
      all_names(n + 1:) = names
      all_values(1:n) = result%report_values
      all_values(n + 1:) = values
      call move_alloc(all_names, result%report_names)
      call move_alloc(all_values, result%report_values)
   end subroutine add_report

   !> The whole state of a run after step `step`: what `restore` continues from.
   subroutine capture(run, result, step, state)
      type(run_state_t), intent(inout) :: run
      type(run_result_t), intent(inout) :: result
      integer, intent(in) :: step
      type(state_t), intent(out) :: state
      integer :: at
      at = step
      state%saving = .true.
      call sync_run(state, run, result, at)
   end subroutine capture

   !> Continue from `state` (a run of this configuration after its step `first` - 1): the run set up and
   !> at its first state takes every running value back; `error` when the state lacks one (a damaged
   !> checkpoint or one of another build).
   subroutine restore(state, run, result, first, error)
      type(state_t), intent(inout) :: state
      type(run_state_t), intent(inout) :: run
      type(run_result_t), intent(inout) :: result
      integer, intent(out) :: first
      type(error_t), allocatable, intent(out) :: error
      integer :: step
      step = -1
      state%saving = .false.
      call sync_run(state, run, result, step)
      if (allocated(state%missing)) then
         call set_error(error, 'it lacks (or holds in another form) '//state%missing)
      else if (step < 0 .or. step > result%steps) then
         call set_error(error, 'its step '//str(step)//' is not one of this run''s 0 .. '//str(result%steps))
      end if
      first = step + 1
   end subroutine restore

   !> A run's whole state to or from `state` (as state%saving says): the particles, the grid, the
   !> stepper's own, the guards' and the scene's running values, the result so far with its history
   !> and snapshots, the step.
   subroutine sync_run(state, run, result, step)
      type(state_t), intent(inout) :: state
      type(run_state_t), intent(inout) :: run
      type(run_result_t), intent(inout) :: result
      integer, intent(inout) :: step
      integer :: k
      logical :: started
      call state%sync('step', step)
      call sync_particles(state, run%particles)
      call sync_grid(state, 'grid', run%grid)
      call run%stepper%sync_state(state)
      ! the scene's watch, made at its first step: restored into an empty one of the scene's type
      started = allocated(run%watch)
      call state%sync('run.watch_started', started)
      if (started) then
         if (.not. allocated(run%watch)) call run%scene%new_watch(run%watch)
         call run%watch%sync(state, 'run.watch')
      end if
      call state%sync('run.next_snapshot', run%next_snapshot)
      call state%sync('run.snapshots_taken', run%snapshots_taken)
      call state%sync('run.total_mass', run%total_mass)
      call state%sync('run.energy_reference', run%energy_reference)
      call state%sync('run.ucm', run%ucm)
      call state%sync('run.energy', run%energy)
      call state%sync('result.steps_done', result%steps_done)
      call state%sync('result.max_error', result%max_error)
      call state%sync('result.initial_energy', result%initial_energy)
      call state%sync('result.final_energy', result%final_energy)
      call state%sync('result.max_energy_ratio', result%max_energy_ratio)
      call state%sync('result.min_volume_ratio', result%min_volume_ratio)
      call state%sync('result.max_cell_move', result%max_cell_move)
      call state%sync('result.min_node_mass_ratio', result%min_node_mass_ratio)
      associate (h => result%history)
         call state%sync('history.recorded', h%recorded)
         call state%sync('history.time', h%time)
         call state%sync('history.ucm', h%ucm)
         call state%sync('history.ucm_exact', h%ucm_exact)
         call state%sync('history.kinetic_energy', h%kinetic_energy)
         call state%sync('history.strain_energy', h%strain_energy)
         call state%sync('history.plastic_work', h%plastic_work)
      end associate
      if (run%snapshots_taken < 0 .or. run%snapshots_taken > size(result%snapshots)) then
         call state%sync('snapshot.count', run%snapshots_taken) ! (noted as missing: not one this run takes)
         return
      end if
      do k = 1, run%snapshots_taken
         call sync_snapshot(state, 'snapshot.'//str(k), result%snapshots(k))
      end do
   end subroutine sync_run

   subroutine sync_snapshot(state, name, s)
      type(state_t), intent(inout) :: state
      character(len=*), intent(in) :: name
      type(snapshot_t), intent(inout) :: s
      character(len=:), allocatable :: names
      integer :: k, n
      call state%sync(name//'.time', s%time)
      call state%sync(name//'.step', s%step)
      call state%sync(name//'.x', s%x)
      call state%sync(name//'.v', s%v)
      call state%sync(name//'.stress', s%stress)
      call state%sync(name//'.volume_ratio', s%volume_ratio)
      call state%sync(name//'.x0', s%x0)
      call state%sync(name//'.youngs_modulus', s%youngs_modulus)
      call state%sync(name//'.body', s%body)
      call state%sync(name//'.plastic_strain', s%plastic_strain)
      call state%sync(name//'.grid_x', s%grid_x)
      call state%sync(name//'.grid_velocity', s%grid_velocity)
      call state%sync(name//'.exact', s%exact)
      ! the exact fields' names, joined (each exact_name_length characters)
      if (state%saving) then
         if (.not. allocated(s%exact_names)) return
         names = ''
         do k = 1, size(s%exact_names)
            names = names//s%exact_names(k)
         end do
         call state%put(name//'.exact_names', names)
      else
         if (allocated(s%exact_names)) deallocate (s%exact_names)
         if (.not. state%has(name//'.exact_names')) return
         call state%get(name//'.exact_names', names)
         n = len(names)/exact_name_length
         allocate (s%exact_names(n))
         do k = 1, n
            s%exact_names(k) = names((k - 1)*exact_name_length + 1:k*exact_name_length)
         end do
      end if
   end subroutine sync_snapshot
end module mpm_simulation
