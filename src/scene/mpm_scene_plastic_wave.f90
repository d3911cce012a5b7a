!> A plastic wave: a bar on [0, L] at rest and stress-free, its left end driven into it at a constant
!> velocity V from t = 0, its right end free. Exact solution of small-strain theory (Kolsky, Stress Waves in
!> Solids, Clarendon 1953, ch. 7; Wang, Foundations of Stress Waves, Elsevier 2007, doi:10.1016/
!> B978-0-08-044494-9.X5000-4, ch. 3) for the elastoplastic law (Young's modulus E, yield stress sigma_y,
!> linear hardening H; c_e = sqrt(E/rho), E_t = E H/(E + H), c_p = sqrt(E_t/rho)), in reference
!> coordinates X, compression negative:
!>   - an elastic precursor at c_e carrying |sigma| = sigma_y and the particle velocity v1 = sigma_y/(rho c_e);
!>   - behind it a plastic front at c_p, behind which v = V and |sigma| = sigma_y + rho c_p (V - v1);
!>   - for V <= v1 (or an elastic law) a single elastic wave at c_e with |sigma| = rho c_e V, v = V.
!> It holds until the precursor reaches the free end (t = L/c_e; longer runs are refused, and the default
!> end time is 0.8 L/c_e). The drive's force is the stress at X = 0, constant in time, so the momentum
!> grows as |sigma(0)| t and u_cm(t) = |sigma(0)| t^2/(2 rho L).
!> The drive follows the bar's end as it moves into the grid: each step the first particle (the end's,
!> at X = l_p) is given the velocity V. The nodes of its support at or behind it (x_I <= x_1: inside the
!> driven end, where the exact velocity is V) are driven at V, f_I = (m_I V - p_I)/dt, as the composite
!> bar drives node 0; the nodes ahead of it get a point force at its position distributed with its shape
!> functions N_I, f_I += lambda N_I, the Lagrange multiplier of the constraint sum_I N_I v_I = V after the
!> grid solve: lambda = (V - sum_I N_I v*_I)/(dt sum_I N_I^2/m_I) over those nodes, v*_I the velocities
!> the solve gives them without it (and V on the nodes behind). So the end particle moves exactly at V,
!> and the nearly empty node it leaves behind as it moves into the grid has the velocity V instead of
!> one that the cell-crossing instability of linear shape functions would blow up. Driving node 0 alone,
!> as the composite bar does, frees the end once it has moved past that node.
!> Error measure: at the end time, the L1 norm of the particle stress minus the exact stress at the
!> particle's reference position, sum_p |sigma_p - sigma(X_p, T)| V0_p (Pa m), relative to the plastic
!> stress times L (relative_error), as the composite bar's.
module mpm_scene_plastic_wave
   use, intrinsic :: ieee_arithmetic, only: ieee_value, ieee_quiet_nan
   use mpm_kinds, only: dp
   use mpm_errors, only: error_t, append_error
   use mpm_strings, only: num, num_at_most, str
   use mpm_settings, only: settings_t
   use mpm_registry, only: parameter_t, short_number
   use mpm_grid, only: grid_t
   use mpm_particles, only: particles_t, particles_init
   use mpm_shape, only: shape_cache_t
   use mpm_material, only: material_t, law_elastoplastic, stored_energy, plastic_work
   use mpm_material_plastic, only: hardening_tangent
   use mpm_scene, only: scene_t, watch_t, margin_for, exact_name_length
   use mpm_loads, only: drive_t
   use mpm_scene_input, only: scene_input_t, scene_kind_t, body_input_t, drive_entry, body_representable, refuse_beyond_doubles
   implicit none
   private
   public :: plastic_wave_t, plastic_wave_init, plastic_wave_input_t

   !> The plastic wave's run length when neither periods nor end_time is given, in precursor transit
   !> times L/c: its exact solution holds until the elastic precursor reaches the free end.
   real(dp), parameter :: plastic_wave_periods = 0.8_dp

   !> The plastic wave's input: its body and the drive velocity V (by default about three times the
   !> default material's yield velocity sigma_y/(rho c_e) = 6.3 m/s, as the materials study drives it, so
   !> that the default run carries both fronts; its law is then elastoplastic, default_law).
   type, extends(body_input_t) :: plastic_wave_input_t
      real(dp) :: drive_velocity = 20.0_dp
   contains
      procedure, nopass :: describe => plastic_wave_describe
      procedure :: entries => plastic_wave_entries
      procedure :: check_run => plastic_wave_check_run
      procedure :: period => plastic_wave_period
      procedure :: default_periods => plastic_wave_default_periods
      procedure :: default_law => plastic_wave_default_law
      procedure :: warnings => plastic_wave_warnings
      procedure :: check_representable => plastic_wave_representable
      procedure :: make => plastic_wave_make
   end type plastic_wave_input_t

   type, extends(scene_t) :: plastic_wave_t
      real(dp) :: length = 0.0_dp, density = 0.0_dp
      real(dp) :: drive_velocity = 0.0_dp        !< V (m/s)
      real(dp) :: elastic_speed = 0.0_dp         !< c_e (m/s)
      real(dp) :: plastic_speed = 0.0_dp         !< c_p (m/s); 0 when nothing yields
      real(dp) :: tangent_modulus = 0.0_dp       !< E_t = E H/(E + H) (Pa)
      real(dp) :: precursor_stress = 0.0_dp      !< |sigma| behind the precursor: sigma_y, or rho c_e V (Pa)
      real(dp) :: precursor_velocity = 0.0_dp    !< v behind the precursor: v1, or V (m/s)
      real(dp) :: plastic_stress = 0.0_dp        !< |sigma| behind the plastic front (the precursor's if none)
      logical :: yields = .false.                !< elastoplastic and V > v1: two fronts
      real(dp) :: dt = 0.0_dp, end_time = 0.0_dp
      type(material_t) :: material               !< for the energies of the balance
   contains
      procedure :: place_particles, margin_cells, fixed_nodes, ucm_exact, ucm_amplitude
      procedure :: add_forces, error_at, error_name, error_unit, energy_reference, report, watch_report
      procedure :: stress_exact, velocity_exact, drive, exact_fields
   end type plastic_wave_t

contains

   pure function plastic_wave_describe() result(kind)
      type(scene_kind_t) :: kind
      kind = scene_kind_t('plastic_wave', 'an elastic-plastic wave from a driven end', &
                          "L/c (the precursor's transit; default 0.8)")
   end function plastic_wave_describe

   subroutine plastic_wave_entries(self, table)
      class(plastic_wave_input_t), intent(inout), target :: self
      type(parameter_t), allocatable, intent(out) :: table(:)
      call self%body_entries(table)
      table = [table, drive_entry(self%drive_velocity)]
   end subroutine plastic_wave_entries

   !> The exact solution holds until the elastic precursor reaches the free end at L/c.
   subroutine plastic_wave_check_run(self, settings, end_time, dx, length_text, error, given)
      class(plastic_wave_input_t), intent(in) :: self
      class(settings_t), intent(in) :: settings
      real(dp), intent(in) :: end_time, dx
      character(len=*), intent(in) :: length_text
      type(error_t), allocatable, intent(inout) :: error
      type(parameter_t), intent(in), optional :: given(:)
      real(dp) :: transit
      transit = self%length/self%wave_speed()
      if (end_time > (1.0_dp + 1.0e-12_dp)*transit) &
         call append_error(error, length_text//" ends after the elastic precursor reaches the free end at L/c = "// &
                           num(transit, 4)// &
                           " s, where the plastic wave's exact solution stops holding; allowed: periods <= 1 "// &
                           "(end_time <= "//num_at_most(transit, 4)//" s)")
   end subroutine plastic_wave_check_run

   !> The elastic precursor's transit time L/c.
   pure real(dp) function plastic_wave_period(self)
      class(plastic_wave_input_t), intent(in) :: self
      plastic_wave_period = self%length/sqrt(self%youngs_modulus/self%density)
   end function plastic_wave_period

   !> Beyond the wave speed (body_input_t): the energy balance sums m v^2/2 and the drive's work V sum m v
   !> as they stand, and the stress rho c V, within the doubles (compared as logarithms).
   subroutine plastic_wave_representable(self, settings, error)
      class(plastic_wave_input_t), intent(in) :: self
      class(settings_t), intent(in) :: settings
      type(error_t), allocatable, intent(inout) :: error
      real(dp) :: log_ratio
      call body_representable(self, settings, error)
      if (allocated(error)) return
      log_ratio = log10(self%youngs_modulus) - log10(self%density)
      call within("the drive's work rho V^2 L", log10(self%density) + 2*log10(self%drive_velocity) + &
                  log10(self%length))
      call within("the stress rho c V", log10(self%density) + log_ratio/2 + log10(self%drive_velocity))
   contains
      !> Refuse the scene when a product its formulas form (log10 `magnitude`) leaves the doubles.
      subroutine within(what, magnitude)
         character(len=*), intent(in) :: what
         real(dp), intent(in) :: magnitude
         call refuse_beyond_doubles(error, "kind = "// &
            "'plastic_wave' with length = "//short_number(self%length)//" m, drive_velocity = "// &
            short_number(self%drive_velocity)//" m/s and youngs_modulus = "//short_number(self%youngs_modulus)// &
            " Pa and density = "//short_number(self%density)//" kg/m^3", what, magnitude)
      end subroutine within
   end subroutine plastic_wave_representable

   !> Elastoplastic when the input names no law: the wave's two fronts.
   function plastic_wave_default_law(self) result(law)
      class(plastic_wave_input_t), intent(in) :: self
      character(len=:), allocatable :: law
      law = 'elastoplastic'
   end function plastic_wave_default_law

   !> A plastic wave that cannot yield (another law than elastoplastic, or a drive at or below the yield
   !> velocity v1 = sigma_y/(rho c_e)) carries one elastic wave and no plastic front: say so ('' otherwise).
   function plastic_wave_warnings(self, settings) result(text)
      class(plastic_wave_input_t), intent(in) :: self
      class(settings_t), intent(in) :: settings
      character(len=:), allocatable :: text
      real(dp) :: v1
      text = ''
      if (trim(settings%law) /= 'elastoplastic') then
         text = "the plastic wave cannot yield with law = '"//trim(settings%law)//"': one elastic wave, no plastic "// &
                "front (law = 'elastoplastic' makes one)"
         return
      end if
      v1 = self%yield_stress/(self%density*sqrt(self%youngs_modulus/self%density))
      if (self%drive_velocity <= v1) text = "the plastic wave cannot yield: drive_velocity = "// &
         short_number(self%drive_velocity)//" m/s is at or below the yield velocity yield_stress/(density c) = "// &
         num(v1, 4)//" m/s: one elastic wave, no plastic front (a faster drive makes one)"
   end function plastic_wave_warnings

   pure real(dp) function plastic_wave_default_periods(self)
      class(plastic_wave_input_t), intent(in) :: self
      plastic_wave_default_periods = plastic_wave_periods
   end function plastic_wave_default_periods

   subroutine plastic_wave_make(self, settings, scene, error)
      class(plastic_wave_input_t), intent(in) :: self
      class(settings_t), intent(in) :: settings
      class(scene_t), allocatable, intent(out) :: scene
      type(error_t), allocatable, intent(out) :: error
      allocate (scene, source=plastic_wave_init(self, settings))
   end subroutine plastic_wave_make

   !> The scene of a validated and resolved configuration.
   pure function plastic_wave_init(input, settings) result(scene)
      type(plastic_wave_input_t), intent(in) :: input
      class(settings_t), intent(in) :: settings
      type(plastic_wave_t) :: scene
      real(dp) :: v1
      scene%external_forces = .true.
      scene%drives = .true.
      scene%watches = .true.  ! (nothing per step; watch_report measures the fronts at the end)
      scene%length = input%length
      scene%density = input%density
      scene%drive_velocity = input%drive_velocity
      scene%elastic_speed = sqrt(input%youngs_modulus/input%density)
      scene%dt = settings%dt
      scene%end_time = settings%steps*settings%dt
      scene%material = input%material(settings%law)
      scene%precursor_stress = input%density*scene%elastic_speed*input%drive_velocity
      scene%precursor_velocity = input%drive_velocity
      scene%plastic_stress = scene%precursor_stress
      if (scene%material%law == law_elastoplastic) then
         v1 = input%yield_stress/(input%density*scene%elastic_speed)
         scene%tangent_modulus = hardening_tangent(input%youngs_modulus, input%hardening_modulus)
         scene%yields = input%drive_velocity > v1
         if (scene%yields) then
            scene%plastic_speed = sqrt(scene%tangent_modulus/input%density)
            scene%precursor_stress = input%yield_stress
            scene%precursor_velocity = v1
            scene%plastic_stress = input%yield_stress + input%density*scene%plastic_speed*(input%drive_velocity - v1)
         end if
      end if
   end function plastic_wave_init

   !> Exact stress at reference position x0 and time t (Pa; compression negative).
   elemental real(dp) function stress_exact(self, x0, t)
      class(plastic_wave_t), intent(in) :: self
      real(dp), intent(in) :: x0, t
      if (x0 < self%plastic_speed*t) then
         stress_exact = -self%plastic_stress
      else if (x0 < self%elastic_speed*t) then
         stress_exact = -self%precursor_stress
      else
         stress_exact = 0.0_dp
      end if
   end function stress_exact

   !> Exact velocity at reference position x0 and time t (m/s).
   elemental real(dp) function velocity_exact(self, x0, t)
      class(plastic_wave_t), intent(in) :: self
      real(dp), intent(in) :: x0, t
      if (x0 < self%plastic_speed*t) then
         velocity_exact = self%drive_velocity
      else if (x0 < self%elastic_speed*t) then
         velocity_exact = self%precursor_velocity
      else
         velocity_exact = 0.0_dp
      end if
   end function velocity_exact

   !> The exact fields at X = x0: the displacement, the time integral of the velocity (each front adds its
   !> velocity jump from its arrival X/c on), the velocity and the stress.
   pure subroutine exact_fields(self, x0, t, names, values)
      class(plastic_wave_t), intent(in) :: self
      real(dp), intent(in) :: x0(:), t
      character(len=exact_name_length), allocatable, intent(out) :: names(:)
      real(dp), allocatable, intent(out) :: values(:, :)
      names = [character(len=exact_name_length) :: 'displacement', 'velocity', 'stress']
      allocate (values(size(x0), 3))
      values(:, 1) = self%precursor_velocity*max(0.0_dp, t - x0/self%elastic_speed)
      if (self%yields) values(:, 1) = values(:, 1) + (self%drive_velocity - self%precursor_velocity)* &
                                      max(0.0_dp, t - x0/self%plastic_speed)
      values(:, 2) = self%velocity_exact(x0, t)
      values(:, 3) = self%stress_exact(x0, t)
   end subroutine exact_fields

   !> As the bar's particles, at rest and unstressed (particle 1 is the driven end's).
   subroutine place_particles(self, settings, particles, error)
      class(plastic_wave_t), intent(in) :: self
      class(settings_t), intent(in) :: settings
      type(particles_t), intent(out) :: particles
      type(error_t), allocatable, intent(out) :: error
      call particles_init(particles, settings%elements, settings%particles_per_element, settings%dx, self%density, &
                          error)
   end subroutine place_particles

   !> The free end stays at rest until the precursor reaches it (after the run): two cells as for the bar.
   pure integer function margin_cells(self, dx, requested) result(cells)
      class(plastic_wave_t), intent(in) :: self
      real(dp), intent(in) :: dx
      integer, intent(in) :: requested
      cells = margin_for(0.0_dp, dx, requested)
   end function margin_cells

   !> No node is held (the drive acts through add_forces).
   pure function fixed_nodes(self) result(nodes)
      class(plastic_wave_t), intent(in) :: self
      integer, allocatable :: nodes(:)
      allocate (nodes(0))
   end function fixed_nodes

   !> u_cm(t) = |sigma(0)| t^2/(2 rho L): the drive's force is constant.
   pure real(dp) function ucm_exact(self, t)
      class(plastic_wave_t), intent(in) :: self
      real(dp), intent(in) :: t
      ucm_exact = self%plastic_stress*t**2/(2.0_dp*self%density*self%length)
   end function ucm_exact

   !> The plastic stress times L (Pa m), the scale of the L1 stress error.
   pure real(dp) function ucm_amplitude(self)
      class(plastic_wave_t), intent(in) :: self
      ucm_amplitude = self%plastic_stress*self%length
   end function ucm_amplitude

   !> The drive (see the module): the nodes at or behind the end particle (x_I <= x_1, inside the driven
   !> end) get the force that gives them the velocity V, f_I = (m_I V - p_I)/dt; the nodes ahead of it the
   !> point force lambda N_I that makes the end particle's interpolated velocity V.
   subroutine add_forces(self, grid, t, cache, particles)
      class(plastic_wave_t), intent(in) :: self
      type(grid_t), intent(inout) :: grid
      real(dp), intent(in) :: t
      type(shape_cache_t), intent(in) :: cache
      type(particles_t), intent(in) :: particles
      real(dp) :: missing, flexibility, w, multiplier, driven_end
      integer :: k, i
      logical :: behind(cache%support)
      missing = self%drive_velocity
      flexibility = 0.0_dp
      driven_end = particles%x(1)
      if (cache%total) driven_end = particles%x0(1) ! (the total-Lagrangian grid is the reference configuration's)
      do k = 1, cache%support
         i = cache%first(1) + k - 1
         w = cache%weight(1, k)
         behind(k) = grid%origin + i*grid%dx <= driven_end
         if (grid%mass(i) <= grid%empty_mass) cycle ! the solve gives it no velocity
         if (behind(k)) then
            grid%force(i) = (grid%mass(i)*self%drive_velocity - grid%momentum(i))/self%dt
            missing = missing - w*self%drive_velocity
         else
            missing = missing - w*(grid%momentum(i) + self%dt*grid%force(i))/grid%mass(i)
            flexibility = flexibility + w*w/grid%mass(i)
         end if
      end do
      if (flexibility <= 0.0_dp) return
      multiplier = missing/(self%dt*flexibility)
      do k = 1, cache%support
         i = cache%first(1) + k - 1
         if (grid%mass(i) <= grid%empty_mass .or. behind(k)) cycle
         grid%force(i) = grid%force(i) + multiplier*cache%weight(1, k)
      end do
   end subroutine add_forces

   !> The drive for the implicit integrators: the end particle (particle 1) moves at V. The nodes of its
   !> support at or behind it (x_I <= x_1: inside the driven end, where the exact velocity is V) are held
   !> at V, and the nodes ahead of it carry the constraint sum_I N_I v_I = V of the end particle's
   !> interpolated velocity (with the nodes behind at V, the same constraint over all its nodes).
   subroutine drive(self, grid, cache, particles, driven)
      class(plastic_wave_t), intent(in) :: self
      type(grid_t), intent(in) :: grid
      type(shape_cache_t), intent(in) :: cache
      type(particles_t), intent(in) :: particles
      type(drive_t), intent(out) :: driven
      integer :: k
      logical :: behind(cache%support)
      behind = [(grid%origin + (cache%first(1) + k - 1)*grid%dx <= particles%x(1), k=1, cache%support)]
      driven%nodes = pack([(cache%first(1) + k - 1, k=1, cache%support)], behind)
      driven%first = cache%first(1)
      driven%weight = merge(0.0_dp, cache%weight(1, :), behind)
      driven%velocity = self%drive_velocity
   end subroutine drive

   !> At the end time: sum_p |sigma_p - sigma(X_p, T)| V0_p (Pa m); 0 before.
   real(dp) function error_at(self, t, particles, ucm)
      class(plastic_wave_t), intent(in) :: self
      real(dp), intent(in) :: t, ucm
      type(particles_t), intent(in) :: particles
      error_at = 0.0_dp
      if (t < self%end_time - 0.5_dp*self%dt) return
      error_at = sum(abs(particles%stress - self%stress_exact(particles%x0, t))*particles%volume0_of)
   end function error_at

   pure function error_name(self) result(name)
      class(plastic_wave_t), intent(in) :: self
      character(len=:), allocatable :: name
      name = 'L1 stress error at the end time'
   end function error_name

   pure function error_unit(self) result(unit)
      class(plastic_wave_t), intent(in) :: self
      character(len=:), allocatable :: unit
      unit = 'Pa m'
   end function error_unit

   !> The drive's work |sigma(0)| V T bounds every energy of the bar; twice that for slack.
   pure real(dp) function energy_reference(self, initial_energy)
      class(plastic_wave_t), intent(in) :: self
      real(dp), intent(in) :: initial_energy
      energy_reference = max(initial_energy, 2.0_dp*self%plastic_stress*self%drive_velocity*self%end_time, &
                             tiny(1.0_dp))
   end function energy_reference

   !> The exact fronts: wave speeds, the stress and velocity behind each (compressive stresses as
   !> magnitudes), their positions at the end time, and whether the bar yields (1) or carries one
   !> elastic wave (0).
   pure subroutine report(self, names, values)
      class(plastic_wave_t), intent(in) :: self
      character(len=32), allocatable, intent(out) :: names(:)
      real(dp), allocatable, intent(out) :: values(:)
      names = [character(len=32) :: 'elastic_wave_speed', 'plastic_wave_speed', 'tangent_modulus', &
               'precursor_stress', 'precursor_velocity', 'plastic_stress', 'precursor_front', 'plastic_front', 'yields']
      values = [self%elastic_speed, self%plastic_speed, self%tangent_modulus, self%precursor_stress, &
                self%precursor_velocity, self%plastic_stress, self%elastic_speed*self%end_time, &
                self%plastic_speed*self%end_time, merge(1.0_dp, 0.0_dp, self%yields)]
   end subroutine report

   !> What the run made of the fronts, at the end time T: each front's position (the largest X_p whose
   !> |sigma_p| reaches half of the front's jump: the precursor's, from 0; the plastic front's, from the
   !> precursor's stress), the mean |sigma_p| over the middle half of the plastic zone [0, c_p T] and of
   !> the elastic zone [c_p T, c_e T], and the energy balance: the drive's work W = V P (its force is
   !> the bar's momentum change, at the constant velocity V) and (kinetic + stored + plastic work - W)/W.
   subroutine watch_report(self, watch, particles, names, values)
      class(plastic_wave_t), intent(in) :: self
      class(watch_t), allocatable, intent(in) :: watch
      type(particles_t), intent(in) :: particles
      character(len=32), allocatable, intent(out) :: names(:)
      real(dp), allocatable, intent(out) :: values(:)
      real(dp), allocatable :: magnitude(:)
      real(dp) :: work, balance, precursor, plastic, front_e, front_p
      magnitude = -particles%stress
      front_e = self%elastic_speed*self%end_time
      front_p = self%plastic_speed*self%end_time
      precursor = maxval(particles%x0, mask=magnitude >= 0.5_dp*self%precursor_stress, dim=1)
      plastic = maxval(particles%x0, mask=magnitude >= 0.5_dp*(self%precursor_stress + self%plastic_stress), dim=1)
      work = self%drive_velocity*sum(particles%mass_of*particles%v)
      ! no work, no balance (a run a guard stopped at its first step): no value, not 0/0
      balance = ieee_value(work, ieee_quiet_nan)
      if (work /= 0.0_dp) balance = (sum(0.5_dp*particles%mass_of*particles%v**2) + &
                                     stored_energy(self%material, particles) + plastic_work(self%material, particles) - &
                                     work)/work
      names = [character(len=32) :: 'measured_precursor_front', 'measured_plastic_front', 'measured_plastic_stress', &
               'measured_precursor_stress', 'drive_work', 'energy_balance']
      values = [max(precursor, 0.0_dp), merge(max(plastic, 0.0_dp), 0.0_dp, self%yields), &
                zone_mean(0.25_dp*front_p, 0.75_dp*front_p), &
                zone_mean(front_p + 0.25_dp*(front_e - front_p), front_p + 0.75_dp*(front_e - front_p)), work, balance]
   contains
      !> Mean |sigma_p| of the particles with X_p in [a, b] (0 if none).
      real(dp) function zone_mean(a, b)
         real(dp), intent(in) :: a, b
         logical, allocatable :: inside(:)
         inside = particles%x0 >= a .and. particles%x0 <= b
         zone_mean = sum(magnitude, mask=inside)/max(count(inside), 1)
      end function zone_mean
   end subroutine watch_report
end module mpm_scene_plastic_wave
