!> A wave through stiff-soft interfaces: a bar of segments (lengths L_i, Young's moduli E_i, densities
!> rho_i, left to right), at rest and unstressed, its left end driven at a constant velocity v from
!> t = 0, its right end free. Exact (linear elasticity, method of characteristics; e.g. Graff, Wave
!> Motion in Elastic Solids, 1975, ch. 2): the solution is a superposition of step waves ("fronts")
!> that cross one segment each at c_i = sqrt(E_i/rho_i). A right-going wave has sigma = -Z v, a
!> left-going one sigma = +Z v (Z = rho c). The drive starts a right-going front of stress -Z_1 v; a front
!> meeting an interface from impedance Z_a to Z_b sends on 2 Z_b/(Z_a + Z_b) times its stress jump and
!> reflects (Z_b - Z_a)/(Z_a + Z_b) times it; it reflects with +1 at the driven end (velocity held)
!> and -1 at the free end (stress zero). The exact stress at (X, t) is the sum of the jumps of the fronts
!> that have passed X. Error measure: at the end time only, the L1 norm of the particle stress minus the
!> exact stress at the particle's reference position, sum_p |sigma_p - sigma(X_p, T)| V0_p, divided by
!> Z_1 v (total length) (relative_error). dt follows the stiffest segment (the resolved wave speed).
!> Needs per-particle mass and Young's modulus, and the driven node 0: its force is set so that the grid
!> solve gives it the drive velocity, f_0 = (m_0 v - p_0)/dt (the reaction force), through add_forces.
module mpm_scene_composite
   use mpm_kinds, only: dp
   use mpm_errors, only: error_t, set_error, append_error
   use mpm_strings, only: str, num
   use mpm_settings, only: settings_t, max_segments
   use mpm_registry, only: parameter_t, short_number, place
   use mpm_grid, only: grid_t, grid_loads_t
   use mpm_particles, only: particles_t, particles_init
   use mpm_shape, only: shape_cache_t
   use mpm_scene, only: scene_t, margin_for, exact_name_length
   use mpm_loads, only: drive_t
   use mpm_scene_input, only: scene_input_t, scene_kind_t, bodies_input_t, drive_entry, most_margin_cells
   implicit none
   private
   public :: composite_t, composite_init, composite_input_t

   !> The composite bar's input: its segments (2 to max_segments) and the drive velocity of its left end.
   type, extends(bodies_input_t) :: composite_input_t
      real(dp) :: drive_velocity = 1.0_dp
   contains
      procedure, nopass :: describe => composite_describe, part => composite_part
      procedure :: entries => composite_entries
      procedure :: check => composite_check
      procedure :: check_run => composite_check_run
      procedure :: body_length => composite_length
      procedure :: period => composite_period
      procedure :: reach => composite_reach
      procedure :: make => composite_make
   end type composite_input_t

   !> Most fronts the exact solution follows (a longer end time is refused).
   integer, parameter :: max_fronts = 2000000

   type, extends(scene_t) :: composite_t
      real(dp), allocatable :: left(:), right(:)   !< segment ends (m)
      real(dp), allocatable :: speed(:), impedance(:), modulus(:), density(:)
      !> each segment's yield stress and hardening modulus (law elastoplastic only; mpm_material)
      real(dp), allocatable :: yield_stress(:), hardening_modulus(:)
      real(dp) :: drive_velocity = 0.0_dp
      real(dp) :: dt = 0.0_dp
      real(dp) :: dx = 0.0_dp
      real(dp) :: end_time = 0.0_dp
      real(dp) :: scale = 0.0_dp        !< Z_1 v (total length): relative_error divides by it
      !> The fronts: segment, direction (+1 right, -1 left), start time at the segment's end, stress jump.
      integer, allocatable :: front_segment(:), front_direction(:)
      real(dp), allocatable :: front_start(:), front_jump(:)
   contains
      procedure :: place_particles, margin_cells, fixed_nodes, ucm_exact, ucm_amplitude
      procedure :: add_forces, error_at, error_name, error_unit, energy_reference, report, fused_applies, grid_loads
      procedure :: stress_exact, drive, exact_fields
   end type composite_t

contains

   pure function composite_describe() result(kind)
      type(scene_kind_t) :: kind
      kind = scene_kind_t('composite_bar', 'a wave through stiff-soft segments, driven at one end', &
                          'sum L_i/c_i, one crossing')
   end function composite_describe

   pure function composite_part() result(name)
      character(len=:), allocatable :: name
      name = 'segment'
   end function composite_part

   subroutine composite_entries(self, table)
      class(composite_input_t), intent(inout), target :: self
      type(parameter_t), allocatable, intent(out) :: table(:)
      call self%bodies_entries(table)
      table = [table, drive_entry(self%drive_velocity)]
   end subroutine composite_entries

   !> 2 to max_segments segments with one value of each list, and the elastoplastic lists as many.
   subroutine composite_check(self, settings, error, given)
      class(composite_input_t), intent(in) :: self
      class(settings_t), intent(in) :: settings
      type(error_t), allocatable, intent(inout) :: error
      type(parameter_t), intent(in), optional :: given(:)
      if (self%length_count < 2 .or. self%modulus_count /= self%length_count .or. &
          self%density_count /= self%length_count) call append_error(error, place(given, 'scene', 'lengths')// &
         "scene: kind = 'composite_bar' needs 2 to "//str(max_segments)//" segments: lengths, youngs_moduli and "// &
         "densities with one value each (given "//str(self%length_count)//", "//str(self%modulus_count)// &
         ", "//str(self%density_count)//")")
      call self%check_bodies_material(settings, error)
   end subroutine composite_check

   !> The driven end's motion over the run must fit the grid's automatic margin (at most 1e8 cells).
   subroutine composite_check_run(self, settings, end_time, dx, length_text, error, given)
      class(composite_input_t), intent(in) :: self
      class(settings_t), intent(in) :: settings
      real(dp), intent(in) :: end_time, dx
      character(len=*), intent(in) :: length_text
      type(error_t), allocatable, intent(inout) :: error
      type(parameter_t), intent(in), optional :: given(:)
      real(dp) :: cells
      cells = self%margin_overflow(settings, end_time, dx)
      if (cells == 0.0_dp) return
      call append_error(error, place(given, 'scene', 'drive_velocity')//"scene: drive_velocity = "// &
                        short_number(self%drive_velocity)//" m/s moves the bar's free end by up to 4 v T = "// &
                        self%margin_overflow_text(end_time, dx, cells, 'margin')//"drive_velocity <= "// &
                        num(self%drive_velocity*most_margin_cells/cells, 4)//" m/s")
   end subroutine composite_check_run

   !> The segments together.
   pure real(dp) function composite_length(self)
      class(composite_input_t), intent(in) :: self
      composite_length = sum(self%lengths(1:self%length_count))
   end function composite_length

   !> The time a wave takes to cross all segments, sum L_i/c_i.
   pure real(dp) function composite_period(self)
      class(composite_input_t), intent(in) :: self
      associate (n => self%length_count)
         composite_period = sum(self%lengths(1:n)/sqrt(self%youngs_moduli(1:n)/self%densities(1:n)))
      end associate
   end function composite_period

   !> 4 v T: a transmitted wave's particle velocity is at most 2 v, doubled at the free end.
   pure real(dp) function composite_reach(self, end_time)
      class(composite_input_t), intent(in) :: self
      real(dp), intent(in) :: end_time
      composite_reach = 4.0_dp*self%drive_velocity*end_time
   end function composite_reach

   subroutine composite_make(self, settings, scene, error)
      class(composite_input_t), intent(in) :: self
      class(settings_t), intent(in) :: settings
      class(scene_t), allocatable, intent(out) :: scene
      type(error_t), allocatable, intent(out) :: error
      type(composite_t) :: composite
      call composite_init(self, settings, composite, error)
      if (allocated(error)) return
      allocate (scene, source=composite)
   end subroutine composite_make

   !> The scene of a resolved configuration (its end time bounds the fronts followed).
   subroutine composite_init(input, settings, scene, error)
      type(composite_input_t), intent(in) :: input
      class(settings_t), intent(in) :: settings
      type(composite_t), intent(out) :: scene
      type(error_t), allocatable, intent(out) :: error
      integer :: n, i
      n = input%length_count
      scene%external_forces = .true.
      scene%drives = .true.
      scene%modulus = input%youngs_moduli(1:n)
      scene%density = input%densities(1:n)
      if (trim(settings%law) == 'elastoplastic') then
         scene%yield_stress = input%yield_stresses(1:n)
         scene%hardening_modulus = input%hardening_moduli(1:n)
      end if
      scene%speed = sqrt(scene%modulus/scene%density)
      scene%impedance = scene%density*scene%speed
      allocate (scene%left(n), scene%right(n))
      scene%left(1) = 0.0_dp
      do i = 1, n
         if (i > 1) scene%left(i) = scene%right(i - 1)
         scene%right(i) = scene%left(i) + input%lengths(i)
      end do
      scene%drive_velocity = input%drive_velocity
      scene%dt = settings%dt
      scene%dx = settings%dx
      scene%end_time = settings%steps*settings%dt
      scene%scale = scene%impedance(1)*input%drive_velocity*scene%right(n)
      call trace_fronts(scene, error)
   end subroutine composite_init

   !> Follow the fronts from the drive's first one until the end time: each front crossing its segment
   !> before then spawns its reflection and transmission (jumps below 1e-15 of the first are dropped).
   subroutine trace_fronts(self, error)
      type(composite_t), intent(inout) :: self
      type(error_t), allocatable, intent(out) :: error
      integer :: count, k, i, d, n, next
      real(dp) :: arrival, jump, za, zb, smallest
      integer, allocatable :: segment(:), direction(:)
      real(dp), allocatable :: start(:), jumps(:)
      n = size(self%left)
      allocate (segment(1024), direction(1024), start(1024), jumps(1024))
      count = 1
      segment(1) = 1
      direction(1) = 1
      start(1) = 0.0_dp
      jumps(1) = -self%impedance(1)*self%drive_velocity
      smallest = 1.0e-15_dp*abs(jumps(1))
      k = 0
      do while (k < count)
         k = k + 1
         i = segment(k)
         d = direction(k)
         arrival = start(k) + (self%right(i) - self%left(i))/self%speed(i)
         if (arrival >= self%end_time) cycle
         jump = jumps(k)
         za = self%impedance(i)
         next = i + d
         if (next < 1) then          ! the driven end: velocity held, stress reflects with +1
            call add(i, 1, arrival, jump)
         else if (next > n) then     ! the free end: stress zero, reflects with -1
            call add(i, -1, arrival, -jump)
         else
            zb = self%impedance(next)
            call add(i, -d, arrival, (zb - za)/(za + zb)*jump)
            call add(next, d, arrival, 2.0_dp*zb/(za + zb)*jump)
         end if
         if (count > max_fronts) then
            call set_error(error, "scene: the composite bar's exact solution needs more than "//str(max_fronts)// &
                           " wave fronts by the end time; allowed: a shorter end_time")
            return
         end if
      end do
      self%front_segment = segment(1:count)
      self%front_direction = direction(1:count)
      self%front_start = start(1:count)
      self%front_jump = jumps(1:count)
   contains
      subroutine add(seg, dir, t0, amount)
         integer, intent(in) :: seg, dir
         real(dp), intent(in) :: t0, amount
         if (abs(amount) < smallest) return
         if (count == size(segment)) then
            segment = [segment, segment]
            direction = [direction, direction]
            start = [start, start]
            jumps = [jumps, jumps]
         end if
         count = count + 1
         segment(count) = seg
         direction(count) = dir
         start(count) = t0
         jumps(count) = amount
      end subroutine add
   end subroutine trace_fronts

   !> Exact stress at reference position x0 and time t: the jumps of the fronts that have passed x0.
   pure real(dp) function stress_exact(self, x0, t) result(stress)
      class(composite_t), intent(in) :: self
      real(dp), intent(in) :: x0, t
      integer :: f, i
      real(dp) :: reach
      stress = 0.0_dp
      do f = 1, size(self%front_jump)
         i = self%front_segment(f)
         if (x0 < self%left(i) .or. x0 >= self%right(i)) cycle
         reach = self%speed(i)*(t - self%front_start(f))
         if (reach <= 0.0_dp) cycle
         if (self%front_direction(f) > 0) then
            if (x0 - self%left(i) <= reach) stress = stress + self%front_jump(f)
         else
            if (self%right(i) - x0 <= reach) stress = stress + self%front_jump(f)
         end if
      end do
   end function stress_exact

   !> The exact fields at X = x0: the stress (stress_exact), the velocity (a front's velocity jump is
   !> -jump/Z going right, +jump/Z going left) and the displacement (each front's velocity jump times the
   !> time since it passed x0).
   pure subroutine exact_fields(self, x0, t, names, values)
      class(composite_t), intent(in) :: self
      real(dp), intent(in) :: x0(:), t
      character(len=exact_name_length), allocatable, intent(out) :: names(:)
      real(dp), allocatable, intent(out) :: values(:, :)
      integer :: f, i, p
      real(dp) :: since, jump
      names = [character(len=exact_name_length) :: 'displacement', 'velocity', 'stress']
      allocate (values(size(x0), 3))
      values = 0.0_dp
      do p = 1, size(x0)
         do f = 1, size(self%front_jump)
            i = self%front_segment(f)
            if (x0(p) < self%left(i) .or. x0(p) >= self%right(i)) cycle
            if (self%front_direction(f) > 0) then
               since = t - self%front_start(f) - (x0(p) - self%left(i))/self%speed(i)
            else
               since = t - self%front_start(f) - (self%right(i) - x0(p))/self%speed(i)
            end if
            if (since < 0.0_dp) cycle
            jump = -self%front_direction(f)*self%front_jump(f)/self%impedance(i)
            values(p, 1) = values(p, 1) + jump*since
            values(p, 2) = values(p, 2) + jump
         end do
         values(p, 3) = self%stress_exact(x0(p), t)
      end do
   end subroutine exact_fields

   !> `particles_per_element` particles per element at the centres of equal sub-cells over the whole
   !> bar, each of the segment holding its centre: its own mass and Young's modulus (and with law
   !> elastoplastic its yield stress and hardening modulus).
   subroutine place_particles(self, settings, particles, error)
      class(composite_t), intent(in) :: self
      class(settings_t), intent(in) :: settings
      type(particles_t), intent(out) :: particles
      type(error_t), allocatable, intent(out) :: error
      integer :: p, i, stat
      call particles_init(particles, settings%elements, settings%particles_per_element, settings%dx, 1.0_dp, error)
      if (allocated(error)) return
      allocate (particles%mass_of(particles%count), particles%volume0_of(particles%count), &
                particles%youngs_modulus_of(particles%count), stat=stat)
      if (stat /= 0) then
         call set_error(error, "cannot allocate per-particle data for "//str(particles%count)// &
                        " particles (out of memory)")
         return
      end if
      particles%volume0_of = particles%volume0
      if (allocated(self%yield_stress)) allocate (particles%yield_stress_of(particles%count), &
                                                  particles%hardening_modulus_of(particles%count), stat=stat)
      if (stat /= 0) then
         call set_error(error, "cannot allocate the plastic parameters of "//str(particles%count)// &
                        " particles (out of memory)")
         return
      end if
      do p = 1, particles%count
         i = segment_of(self, particles%x(p))
         particles%mass_of(p) = self%density(i)*particles%volume0
         particles%youngs_modulus_of(p) = self%modulus(i)
         if (allocated(self%yield_stress)) then
            particles%yield_stress_of(p) = self%yield_stress(i)
            particles%hardening_modulus_of(p) = self%hardening_modulus(i)
         end if
      end do
      particles%mass = minval(particles%mass_of) ! the scale of "empty" nodes and of guard messages
   end subroutine place_particles

   pure integer function segment_of(self, x) result(i)
      class(composite_t), intent(in) :: self
      real(dp), intent(in) :: x
      do i = 1, size(self%left) - 1
         if (x < self%right(i)) return
      end do
      i = size(self%left)
   end function segment_of

   !> Beyond the free end: its largest excursion, at most 4 v T (a transmitted wave's particle velocity
   !> is at most 2 v, doubled at the free end), in cells, plus two cells as for the bar.
   pure integer function margin_cells(self, dx, requested) result(cells)
      class(composite_t), intent(in) :: self
      real(dp), intent(in) :: dx
      integer, intent(in) :: requested
      cells = margin_for(4.0_dp*self%drive_velocity*self%end_time, dx, requested)
   end function margin_cells

   !> No node is held at rest (node 0 is driven, through add_forces).
   pure function fixed_nodes(self) result(nodes)
      class(composite_t), intent(in) :: self
      integer, allocatable :: nodes(:)
      allocate (nodes(0))
   end function fixed_nodes

   !> Exact centre-of-mass displacement (for the history): the bar's momentum grows by the drive's force
   !> -sigma(0, t), a step function of time (each front of segment 1 adds its jump when it passes x = 0:
   !> a right-going one at its start, a left-going one a crossing time later), so
   !> M u_cm(t) = -sum_f jump_f (t - t_f)^2/2 over the fronts with t_f < t, M = sum rho_i L_i.
   pure real(dp) function ucm_exact(self, t)
      class(composite_t), intent(in) :: self
      real(dp), intent(in) :: t
      integer :: f
      real(dp) :: passes
      ucm_exact = 0.0_dp
      do f = 1, size(self%front_jump)
         if (self%front_segment(f) /= 1) cycle
         passes = self%front_start(f)
         if (self%front_direction(f) < 0) passes = passes + (self%right(1) - self%left(1))/self%speed(1)
         if (t > passes) ucm_exact = ucm_exact - self%front_jump(f)*(t - passes)**2/2.0_dp
      end do
      ucm_exact = ucm_exact/sum(self%density*(self%right - self%left))
   end function ucm_exact

   !> Z_1 v (total length), the scale of the L1 stress error (Pa m).
   pure real(dp) function ucm_amplitude(self)
      class(composite_t), intent(in) :: self
      ucm_amplitude = self%scale
   end function ucm_amplitude

   !> The driven node 0: the force that brings its momentum to m_0 v in this step's solve.
   subroutine add_forces(self, grid, t, cache, particles)
      class(composite_t), intent(in) :: self
      type(grid_t), intent(inout) :: grid
      real(dp), intent(in) :: t
      type(shape_cache_t), intent(in) :: cache
      type(particles_t), intent(in) :: particles
      grid%force(0) = (grid%mass(0)*self%drive_velocity - grid%momentum(0))/self%dt
   end subroutine add_forces

   !> The fused kernels take the composite bar (per-particle masses and moduli; the drive is a grid load).
   pure logical function fused_applies(self)
      class(composite_t), intent(in) :: self
      fused_applies = .true.
   end function fused_applies

   !> The driven node 0 as a grid load: its force set to (m_0 v - p_0)/dt where the fused kernels
   !> assemble the nodal force (the same expression as add_forces).
   pure function grid_loads(self) result(loads)
      class(composite_t), intent(in) :: self
      type(grid_loads_t) :: loads
      loads = grid_loads_t(acceleration=0.0_dp, driven_node=0, drive_velocity=self%drive_velocity, drive_dt=self%dt)
   end function grid_loads

   !> The drive for the implicit integrators: node 0 held at the drive velocity (as add_forces holds it).
   subroutine drive(self, grid, cache, particles, driven)
      class(composite_t), intent(in) :: self
      type(grid_t), intent(in) :: grid
      type(shape_cache_t), intent(in) :: cache
      type(particles_t), intent(in) :: particles
      type(drive_t), intent(out) :: driven
      driven%nodes = [0]
      allocate (driven%weight(0))
      driven%velocity = self%drive_velocity
   end subroutine drive

   !> At the end time: sum_p |sigma_p - sigma(X_p, T)| V0_p (Pa m); 0 before.
   real(dp) function error_at(self, t, particles, ucm)
      class(composite_t), intent(in) :: self
      real(dp), intent(in) :: t, ucm
      type(particles_t), intent(in) :: particles
      integer :: p
      error_at = 0.0_dp
      if (t < self%end_time - 0.5_dp*self%dt) return
      do p = 1, particles%count
         error_at = error_at + abs(particles%stress(p) - self%stress_exact(particles%x0(p), t))*particles%volume0_of(p)
      end do
   end function error_at

   !> The largest impedance over the smallest, the softest segment's Courant number c_min dt/dx (the
   !> stiffest's is dt_fraction) and the number of wave fronts the exact solution followed.
   pure subroutine report(self, names, values)
      class(composite_t), intent(in) :: self
      character(len=32), allocatable, intent(out) :: names(:)
      real(dp), allocatable, intent(out) :: values(:)
      names = [character(len=32) :: 'impedance_ratio', 'softest_courant_number', 'exact_fronts']
      values = [maxval(self%impedance)/minval(self%impedance), minval(self%speed)*self%dt/self%dx, &
                real(size(self%front_jump), dp)]
   end subroutine report

   pure function error_name(self) result(name)
      class(composite_t), intent(in) :: self
      character(len=:), allocatable :: name
      name = 'L1 stress error at the end time'
   end function error_name

   pure function error_unit(self) result(unit)
      class(composite_t), intent(in) :: self
      character(len=:), allocatable :: unit
      unit = 'Pa m'
   end function error_unit

   !> The drive's work bounds the energy: |sigma| v T with |sigma| at most 2 Z_max v, twice for slack.
   pure real(dp) function energy_reference(self, initial_energy)
      class(composite_t), intent(in) :: self
      real(dp), intent(in) :: initial_energy
      energy_reference = max(initial_energy, 4.0_dp*maxval(self%impedance)*self%drive_velocity**2*self%end_time, &
                             tiny(1.0_dp))
   end function energy_reference
end module mpm_scene_composite
