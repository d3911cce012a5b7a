!> Two bars colliding: bar 1 on [0, L1], bar 2 on [L1 + gap, L1 + gap + L2], lengths L_b, Young's
!> moduli E_b, densities rho_b, uniform initial velocities v_b, unstressed, all ends free. Contact
!> 'frictionless' gives each bar its own velocity field on the grid (mpm_contact: the bars share the
!> centre-of-mass velocity at a node only while they approach there, so they can separate);
!> 'none' gives them one shared field (they stick once they share a node).
!> Exact (linear elasticity, e.g. Graff, Wave Motion in Elastic Solids, 1975, sec. 2.1; Johnson, Impact
!> Strength of Materials, 1972, ch. 1), for equal impedances Z = rho_b c_b (the validation refuses
!> others): the bars meet at t0 = gap/(v1 - v2) when v1 > v2; a compression wave of stress
!> sigma = -Z (v1 - v2)/2 runs into each, the interface moving at (v1 + v2)/2. Frictionless: the
!> release from the free end of the bar with the shorter round trip 2 L/c reaches the interface after
!> tau = 2 min(L_b/c_b) and unloads it; the bars separate. Bar 1's only external force is the
!> interface's, sigma for t0 < t < t0 + tau, so its centre of mass follows
!>   u_cm,1(t) = v1 t + (sigma/M1) [s^2/2 + tau max(0, t - t0 - tau)],  s = min(max(t - t0, 0), tau),
!> M1 = rho_1 L1 (identical bars at +-v, no gap: v t - v c t^2/(2L) until 2L/c, then at -v: the
!> velocities are exchanged). Contact 'none' (equal transit times T = L_b/c_b, also checked): the stuck
!> bars are one free-free bar; the interface stress alternates sigma, -sigma over phases of 2T.
!> Error measure: max over steps of |u_cm,1 - u_cm,1 exact|, relative to v L1/c1 with v = |v1 - v2|/2.
!> Reports (watch_step): the contact time (steps in which bar 1's momentum changed: the only force on
!> it is the other bar's), the largest compressive stress, each bar's final velocity, the total
!> momentum's largest change (round-off) and the exact values to compare with.
module mpm_scene_impact
   use mpm_kinds, only: dp
   use mpm_errors, only: error_t, set_error
   use mpm_strings, only: str
   use mpm_config, only: config_t
   use mpm_particles, only: particles_t, particles_init
   use mpm_diagnostics, only: pass_totals_t
   use mpm_scene, only: scene_t, margin_for
   use mpm_lanes, only: smallest_value
   implicit none
   private
   public :: impact_t, impact_init

   !> Entries of the watch array (watch_step).
   integer, parameter :: w_steps = 1, w_first = 2, w_last = 3, w_min_stress = 4, w_drift = 5, w_momentum1 = 6, &
                         w_momentum0 = 7, w_mass1 = 8, w_size = 8

   type, extends(scene_t) :: impact_t
      real(dp) :: length(2) = 0.0_dp, modulus(2) = 0.0_dp, density(2) = 0.0_dp, speed(2) = 0.0_dp
      !> each bar's yield stress and hardening modulus (law elastoplastic only; mpm_material)
      logical :: plastic = .false.
      real(dp) :: yield_stress(2) = 0.0_dp, hardening_modulus(2) = 0.0_dp
      real(dp) :: velocity(2) = 0.0_dp
      real(dp) :: gap = 0.0_dp
      real(dp) :: mass(2) = 0.0_dp        !< rho_b L_b (kg per unit area)
      real(dp) :: dt = 0.0_dp, end_time = 0.0_dp
      real(dp) :: start = huge(1.0_dp)    !< t0, when the bars meet (huge: never)
      real(dp) :: stress = 0.0_dp         !< interface stress while pressed, -Z (v1 - v2)/2 (Pa)
      real(dp) :: phase = 0.0_dp          !< tau (frictionless) or 2T (none): length of a loading phase
      logical :: stick = .false.          !< contact = 'none': the phases alternate for ever
   contains
      procedure :: place_particles, margin_cells, left_margin_cells, fixed_nodes, ucm_exact, ucm_amplitude
      procedure :: error_at, error_name, report, watch_step, watch_report, fused_applies
      procedure :: bar1_exact, bar1_velocity
   end type impact_t

contains

   !> The scene of a validated and resolved configuration.
   pure function impact_init(config) result(scene)
      type(config_t), intent(in) :: config
      type(impact_t) :: scene
      scene%body_fields = trim(config%contact) == 'frictionless'
      scene%stick = .not. scene%body_fields
      scene%watches = .true.
      scene%length = config%lengths(1:2)
      scene%modulus = config%youngs_moduli(1:2)
      scene%density = config%densities(1:2)
      scene%plastic = trim(config%law) == 'elastoplastic'
      if (scene%plastic) then
         scene%yield_stress = config%yield_stresses(1:2)
         scene%hardening_modulus = config%hardening_moduli(1:2)
      end if
      scene%speed = sqrt(scene%modulus/scene%density)
      scene%velocity = config%velocities(1:2)
      scene%gap = config%gap
      scene%mass = scene%density*scene%length
      scene%dt = config%dt
      scene%end_time = config%steps*config%dt
      if (scene%velocity(1) > scene%velocity(2)) then
         scene%start = scene%gap/(scene%velocity(1) - scene%velocity(2))
         scene%stress = -scene%density(1)*scene%speed(1)*(scene%velocity(1) - scene%velocity(2))/2.0_dp
      end if
      if (scene%stick) then
         scene%phase = 2.0_dp*scene%length(1)/scene%speed(1)
      else
         scene%phase = 2.0_dp*minval(scene%length/scene%speed)
      end if
   end function impact_init

   !> Displacement and velocity of bar 1's centre of mass from the interface force alone, s after t0:
   !> acceleration sigma/M1 in the first phase, then none (frictionless) or alternating signs (stuck).
   pure subroutine interface_motion(self, s, w, wv)
      class(impact_t), intent(in) :: self
      real(dp), intent(in) :: s
      real(dp), intent(out) :: w, wv
      real(dp) :: rest, h, a
      w = 0.0_dp
      wv = 0.0_dp
      rest = s
      a = self%stress/self%mass(1)
      do while (rest > 0.0_dp)
         h = min(rest, self%phase)
         w = w + wv*h + a*h**2/2.0_dp
         wv = wv + a*h
         rest = rest - h
         if (self%stick) then
            a = -a
         else
            w = w + wv*rest  ! then free flight
            exit
         end if
      end do
   end subroutine interface_motion

   !> Exact displacement of bar 1's centre of mass at time t (m).
   pure real(dp) function bar1_exact(self, t)
      class(impact_t), intent(in) :: self
      real(dp), intent(in) :: t
      real(dp) :: w, wv
      call interface_motion(self, t - self%start, w, wv)
      bar1_exact = self%velocity(1)*t + w
   end function bar1_exact

   !> Exact velocity of bar 1's centre of mass at time t (m/s).
   pure real(dp) function bar1_velocity(self, t)
      class(impact_t), intent(in) :: self
      real(dp), intent(in) :: t
      real(dp) :: w, wv
      call interface_motion(self, t - self%start, w, wv)
      bar1_velocity = self%velocity(1) + wv
   end function bar1_velocity

   !> Each bar's elements: its length in cells of the run's dx (at least one), `particles_per_element`
   !> particles in each at the centres of equal sub-cells; bar 1's particles first (body 1), then
   !> bar 2's (body 2), each with its bar's mass, Young's modulus and velocity.
   subroutine place_particles(self, config, particles, error)
      class(impact_t), intent(in) :: self
      type(config_t), intent(in) :: config
      type(particles_t), intent(out) :: particles
      type(error_t), allocatable, intent(out) :: error
      integer :: cells(2), b, k, p, stat, per_bar
      real(dp) :: sub, left
      cells = max(1, nint(self%length/config%dx))
      call particles_init(particles, sum(cells), config%particles_per_element, config%dx, 1.0_dp, error)
      if (allocated(error)) return
      allocate (particles%mass_of(particles%count), particles%volume0_of(particles%count), &
                particles%youngs_modulus_of(particles%count), particles%body(particles%count), stat=stat)
      if (stat == 0 .and. self%plastic) allocate (particles%yield_stress_of(particles%count), &
                                                  particles%hardening_modulus_of(particles%count), stat=stat)
      if (stat /= 0) then
         call set_error(error, "cannot allocate per-particle data for "//str(particles%count)// &
                        " particles (out of memory)")
         return
      end if
      p = 0
      do b = 1, 2
         per_bar = cells(b)*config%particles_per_element
         sub = self%length(b)/per_bar
         left = merge(0.0_dp, self%length(1) + self%gap, b == 1)
         do k = 1, per_bar
            p = p + 1
            particles%x(p) = left + (k - 0.5_dp)*sub
            particles%cell(p) = min(int(particles%x(p)/config%dx) + 1, config%elements)
            particles%volume0_of(p) = sub
            particles%mass_of(p) = self%density(b)*sub
            particles%youngs_modulus_of(p) = self%modulus(b)
            if (self%plastic) then
               particles%yield_stress_of(p) = self%yield_stress(b)
               particles%hardening_modulus_of(p) = self%hardening_modulus(b)
            end if
            particles%v(p) = self%velocity(b)
            particles%body(p) = b
         end do
      end do
      particles%x0 = particles%x
      particles%mass = minval(particles%mass_of) ! the scale of "empty" nodes and of guard messages
      particles%volume0 = minval(particles%volume0_of)
   end subroutine place_particles

   !> How far a free end can move out: at most the faster bar's speed times the run (equal impedances:
   !> every particle velocity stays between v1 and v2), with half as much again for slack.
   pure real(dp) function reach(self)
      class(impact_t), intent(in) :: self
      reach = 1.5_dp*maxval(abs(self%velocity))*self%end_time
   end function reach

   pure integer function margin_cells(self, dx, requested) result(cells)
      class(impact_t), intent(in) :: self
      real(dp), intent(in) :: dx
      integer, intent(in) :: requested
      cells = margin_for(reach(self), dx, requested)
   end function margin_cells

   !> Bar 1's free left end moves out too: as many cells left of x = 0.
   pure integer function left_margin_cells(self, dx, requested) result(cells)
      class(impact_t), intent(in) :: self
      real(dp), intent(in) :: dx
      integer, intent(in) :: requested
      cells = margin_for(reach(self), dx, requested)
   end function left_margin_cells

   pure function fixed_nodes(self) result(nodes)
      class(impact_t), intent(in) :: self
      integer, allocatable :: nodes(:)
      allocate (nodes(0))
   end function fixed_nodes

   !> The whole system's centre of mass (for the history): it moves at the total momentum over the
   !> total mass, whatever the contact.
   pure real(dp) function ucm_exact(self, t)
      class(impact_t), intent(in) :: self
      real(dp), intent(in) :: t
      ucm_exact = sum(self%mass*self%velocity)/sum(self%mass)*t
   end function ucm_exact

   !> v L1/c1, v = |v1 - v2|/2 (the largest |v_b| if they are equal, 1 m/s if both are 0).
   pure real(dp) function ucm_amplitude(self)
      class(impact_t), intent(in) :: self
      real(dp) :: v
      v = abs(self%velocity(1) - self%velocity(2))/2.0_dp
      if (v == 0.0_dp) v = maxval(abs(self%velocity))
      if (v == 0.0_dp) v = 1.0_dp
      ucm_amplitude = v*self%length(1)/self%speed(1)
   end function ucm_amplitude

   !> The fused kernels take the impact (each bar one mass, volume and modulus; frictionless contact on
   !> stacked fields).
   pure logical function fused_applies(self)
      class(impact_t), intent(in) :: self
      fused_applies = .true.
   end function fused_applies

   !> |u_cm,1 - u_cm,1 exact| (m), bar 1's centre of mass from its particles (run_simulation takes it
   !> from watch_step, which sums the same terms in the same order).
   real(dp) function error_at(self, t, particles, ucm)
      class(impact_t), intent(in) :: self
      real(dp), intent(in) :: t, ucm
      type(particles_t), intent(in) :: particles
      real(dp) :: moment, mass, bar1, total
      call step_sums(particles, moment, mass, bar1, total)
      error_at = abs(moment/mass - self%bar1_exact(t))
   end function error_at

   pure function error_name(self) result(name)
      class(impact_t), intent(in) :: self
      character(len=:), allocatable :: name
      name = '|u_cm,1 - u_cm,1 exact| (bar 1)'
   end function error_name

   !> The exact contact start and duration (within the run), interface stress and final velocities.
   pure subroutine report(self, names, values)
      class(impact_t), intent(in) :: self
      character(len=32), allocatable, intent(out) :: names(:)
      real(dp), allocatable, intent(out) :: values(:)
      real(dp) :: start, duration, v1
      start = min(self%start, self%end_time)
      if (self%stick) then
         duration = self%end_time - start
      else
         duration = min(self%phase, self%end_time - start)
      end if
      v1 = self%bar1_velocity(self%end_time)
      names = [character(len=32) :: 'exact_contact_start', 'exact_contact_time', 'exact_interface_stress', &
               'exact_final_velocity_1', 'exact_final_velocity_2']
      values = [start, duration, merge(self%stress, 0.0_dp, start < self%end_time), v1, &
                self%velocity(2) - (v1 - self%velocity(1))*self%mass(1)/self%mass(2)]
   end subroutine report

   !> In one pass over the particles: bar 1's sum_p m_p (x_p - X_p) and mass over its particles, which come
   !> first (to the first particle of another body), and bar 1's and the total momentum, each summed in
   !> particle order. Over bar 1's leading particles the two momenta add the same terms in the same order,
   !> so one sum serves both there (three chains of dependent additions in that loop, two after it,
   !> where the error measure and the momenta took two passes and four chains).
   pure subroutine step_sums(particles, moment, mass, bar1, total)
      type(particles_t), intent(in) :: particles
      real(dp), intent(out) :: moment, mass, bar1, total
      integer :: p, first_other
      moment = 0.0_dp
      mass = 0.0_dp
      bar1 = 0.0_dp
      first_other = particles%count + 1
      do p = 1, particles%count
         if (particles%body(p) /= 1) then
            first_other = p
            exit
         end if
         moment = moment + particles%mass_of(p)*(particles%x(p) - particles%x0(p))
         mass = mass + particles%mass_of(p)
         bar1 = bar1 + particles%mass_of(p)*particles%v(p)
      end do
      total = bar1
      do p = first_other, particles%count
         if (particles%body(p) == 1) bar1 = bar1 + particles%mass_of(p)*particles%v(p)
         total = total + particles%mass_of(p)*particles%v(p)
      end do
   end subroutine step_sums

   !> After each step: whether bar 1's momentum changed (contact), the smallest stress, the total
   !> momentum's drift from its initial value sum_p m_p v_b; and the step's error measure (error_at's).
   !> On stacked fields the fused kernels have summed each bar's m (x - X) and m v, and found the smallest
   !> stress, in their pass (`totals`, summed in lanes: these measures then differ from the particle-order
   !> sums at round-off), and no pass over the particles is made here.
   subroutine watch_step(self, t, particles, totals, ucm, watch, error)
      class(impact_t), intent(in) :: self
      real(dp), intent(in) :: t, ucm
      type(particles_t), intent(in) :: particles
      type(pass_totals_t), intent(in) :: totals
      real(dp), allocatable, intent(inout) :: watch(:)
      real(dp), intent(out) :: error
      real(dp) :: moment, mass, bar1, total, scale, smallest
      if (.not. allocated(watch)) then
         allocate (watch(w_size))
         watch = 0.0_dp
         watch(w_first) = huge(1.0_dp)
         watch(w_min_stress) = 0.0_dp
         watch(w_momentum1) = self%velocity(1)*sum(particles%mass_of, mask=particles%body == 1)
         watch(w_momentum0) = self%velocity(1)*sum(particles%mass_of, mask=particles%body == 1) + &
                              self%velocity(2)*sum(particles%mass_of, mask=particles%body == 2)
         call step_sums(particles, moment, watch(w_mass1), bar1, total) ! (bar 1's mass, as error_at sums it)
      end if
      if (totals%bodies == 2) then ! (each bar a body on stacked fields: body b is bar b)
         moment = totals%body_displacement(1)
         mass = watch(w_mass1)
         bar1 = totals%body_momentum(1)
         total = totals%body_momentum(1) + totals%body_momentum(2)
         smallest = totals%min_stress
      else
         call step_sums(particles, moment, mass, bar1, total)
         smallest = smallest_value(particles%stress)
      end if
      error = abs(moment/mass - self%bar1_exact(t))
      scale = sum(self%mass*abs(self%velocity))
      if (abs(bar1 - watch(w_momentum1)) > 1.0e-9_dp*scale) then
         watch(w_steps) = watch(w_steps) + 1.0_dp
         watch(w_first) = min(watch(w_first), t - self%dt)
         watch(w_last) = t
      end if
      watch(w_momentum1) = bar1
      watch(w_min_stress) = min(watch(w_min_stress), smallest)
      watch(w_drift) = max(watch(w_drift), abs(total - watch(w_momentum0)))
   end subroutine watch_step

   !> contact_time (steps in contact times dt), contact_start and contact_end, the largest compressive
   !> stress (Pa, positive), each bar's final centre-of-mass velocity, the final total momentum and
   !> its largest change over the run relative to sum_b M_b |v_b|.
   subroutine watch_report(self, watch, particles, names, values)
      class(impact_t), intent(in) :: self
      real(dp), allocatable, intent(in) :: watch(:)
      type(particles_t), intent(in) :: particles
      character(len=32), allocatable, intent(out) :: names(:)
      real(dp), allocatable, intent(out) :: values(:)
      real(dp) :: final(2), total, scale
      integer :: b
      names = [character(len=32) :: 'contact_time', 'contact_start', 'contact_end', 'max_compressive_stress', &
               'final_velocity_1', 'final_velocity_2', 'final_momentum', 'momentum_change']
      if (.not. allocated(watch)) then ! no step done
         allocate (values(size(names)))
         values = 0.0_dp
         return
      end if
      do b = 1, 2
         final(b) = sum(particles%mass_of*particles%v, mask=particles%body == b)/ &
                    sum(particles%mass_of, mask=particles%body == b)
      end do
      total = sum(particles%mass_of*particles%v)
      scale = max(sum(self%mass*abs(self%velocity)), tiny(1.0_dp))
      values = [watch(w_steps)*self%dt, merge(0.0_dp, watch(w_first), watch(w_steps) == 0.0_dp), watch(w_last), &
                -watch(w_min_stress), final(1), final(2), total, watch(w_drift)/scale]
   end subroutine watch_report
end module mpm_scene_impact
