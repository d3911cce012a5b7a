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
   use mpm_errors, only: error_t, set_error, append_error
   use mpm_strings, only: str, num, num_at_most
   use mpm_settings, only: settings_t
   use mpm_registry, only: parameter_t, real_entry, real_list_entry, text_entry, short_number, place, in_list
   use mpm_particles, only: particles_t, particles_init
   use mpm_pass_totals, only: pass_totals_t
   use mpm_state, only: state_t
   use mpm_scene, only: scene_t, watch_t, margin_for
   use mpm_lanes, only: smallest_value
   use mpm_scene_input, only: scene_input_t, scene_kind_t, bodies_input_t, most_margin_cells
   implicit none
   private
   public :: impact_t, impact_init, impact_input_t

   !> The impact's input: its two bars (lengths, youngs_moduli, densities: two values each), their
   !> initial velocities, the gap between them and the contact model.
   type, extends(bodies_input_t) :: impact_input_t
      real(dp) :: velocities(2) = 0.0_dp
      integer :: velocity_count = 0
      real(dp) :: gap = 0.0_dp
      character(len=16) :: contact = 'frictionless'
   contains
      procedure, nopass :: describe => impact_describe, part => impact_part
      procedure :: entries => impact_entries
      procedure :: amplitude_source => impact_amplitude_source
      procedure :: check => impact_check
      procedure :: check_run => impact_check_run
      procedure :: body_length => impact_length
      procedure :: period => impact_period
      procedure :: periods_from => contact_time
      procedure :: reach => impact_reach
      procedure :: free_ends => impact_free_ends
      procedure :: warnings => impact_warnings
      procedure :: start_note => impact_start_note
      procedure :: make => impact_make
   end type impact_input_t

   !> What the impact watches over the steps (watch_step) for its report (watch_report).
   type, extends(watch_t) :: impact_watch_t
      real(dp) :: steps = 0.0_dp                     !< steps in which bar 1's momentum changed (in contact)
      real(dp) :: first = huge(1.0_dp), last = 0.0_dp  !< the first such step's start and the last one's end (s)
      real(dp) :: min_stress = 0.0_dp                !< the smallest stress met (Pa)
      real(dp) :: drift = 0.0_dp                     !< the total momentum's largest change from momentum0
      real(dp) :: momentum1 = 0.0_dp                 !< bar 1's momentum after the last step
      real(dp) :: momentum0 = 0.0_dp                 !< the initial total momentum, sum_p m_p v_b
      real(dp) :: mass1 = 0.0_dp                     !< bar 1's mass, as error_at sums it
   contains
      procedure :: sync => impact_watch_sync
   end type impact_watch_t

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
      procedure :: new_watch => impact_new_watch
   end type impact_t

contains

   pure function impact_describe() result(kind)
      type(scene_kind_t) :: kind
      kind = scene_kind_t('impact', 'two bars colliding', '2 max L/c, from their first contact')
   end function impact_describe

   pure function impact_part() result(name)
      character(len=:), allocatable :: name
      name = 'bar'
   end function impact_part

   subroutine impact_entries(self, table)
      class(impact_input_t), intent(inout), target :: self
      type(parameter_t), allocatable, intent(out) :: table(:)
      call self%bodies_entries(table)
      table = [table, real_list_entry('scene', 'velocities', self%velocities, self%velocity_count, 'm/s', &
                                      'initial velocity of bar 1 (left) and bar 2 (right)', note='two values'), &
               real_entry('scene', 'gap', self%gap, 'm', 'distance between bar 1 (on [0, L1]) and bar 2', &
                          at_least=0.0_dp, sweep_list='gaps'), &
               text_entry('scene', 'contact', self%contact, "'none': one shared velocity field (the bars "// &
                          "stick); 'frictionless': a field per bar, the centre-of-mass velocity where they "// &
                          "approach (docs/user-guide.md, impact)", words='none, frictionless', sweep_list='contacts')]
   end subroutine impact_entries

   !> The two bars: two values of each list, the configurations its exact solution covers (equal
   !> impedances rho c, and for contact = 'none', the bars stuck, equal wave transit times L/c); a grid
   !> that resolves both bars (`elements` spans both bars and the gap, and a bar shorter than half a cell
   !> would get a cell of its own it does not fill); the elastoplastic lists; one velocity field for the
   !> implicit integrators (a field per body's contact is a non-smooth constraint Newton does not take).
   subroutine impact_check(self, settings, error, given)
      class(impact_input_t), intent(in) :: self
      class(settings_t), intent(in) :: settings
      type(error_t), allocatable, intent(inout) :: error
      type(parameter_t), intent(in), optional :: given(:)
      real(dp) :: z(2), transit(2), dx, shortest
      integer :: b
      if (self%length_count /= 2 .or. self%modulus_count /= 2 .or. self%density_count /= 2 .or. &
          self%velocity_count /= 2) then
         call append_error(error, place(given, 'scene', 'lengths')//"scene: kind = 'impact' needs two bars: "// &
                           "lengths, youngs_moduli, densities and velocities with two values each (given "// &
                           str(self%length_count)//", "//str(self%modulus_count)//", "// &
                           str(self%density_count)//", "//str(self%velocity_count)//")")
      else
         z = sqrt(self%youngs_moduli(1:2)*self%densities(1:2))
         transit = self%lengths(1:2)/sqrt(self%youngs_moduli(1:2)/self%densities(1:2))
         if (abs(z(1) - z(2)) > 1.0e-9_dp*maxval(z)) call append_error(error, place(given, 'scene', 'youngs_moduli')// &
            "scene: kind = 'impact' needs equal impedances sqrt(youngs_moduli*densities) of the two bars (its exact "// &
            "solution covers those); given "//num(z(1), 6)//" and "//num(z(2), 6)//" kg/(m^2 s)")
         if (trim(self%contact) == 'none' .and. abs(transit(1) - transit(2)) > 1.0e-9_dp*maxval(transit)) &
            call append_error(error, place(given, 'scene', 'contact')//"scene: kind = 'impact' with contact = 'none' "// &
                              "needs equal wave transit times lengths/c of the two bars (the stuck bars' exact "// &
                              "solution); given "//num(transit(1), 6)//" and "//num(transit(2), 6)//" s")
         dx = self%body_length()/settings%elements
         shortest = minval(self%lengths(1:2))
         b = minloc(self%lengths(1:2), 1)
         if (shortest < 0.5_dp*dx) then
            call append_error(error, place(given, 'scene', 'gap')//"scene: gap = "//short_number(self%gap)// &
                              " m with lengths = "//short_number(self%lengths(1))//", "// &
                              short_number(self%lengths(2))//" m on elements = "//str(settings%elements)//" gives "// &
                              "cells of dx = (lengths(1) + gap + lengths(2))/elements = "//num(dx, 4)//" m, more "// &
                              "than twice bar "//str(b)//"'s length: the grid cannot resolve it; allowed: dx <= 2 "// &
                              "lengths("//str(b)//"), that is gap <= "//num_at_most(max(0.0_dp, 2*shortest* &
                              settings%elements - sum(self%lengths(1:2))), 4)//" m at elements = "// &
                              str(settings%elements)//" (or elements >= "// &
                              str(ceiling(min(self%body_length()/(2*shortest), real(huge(1), dp))))//")")
         end if
      end if
      call self%check_bodies_material(settings, error)
      if ((trim(settings%integrator) == 'implicit' .or. trim(settings%integrator) == 'quasi_static') .and. &
          trim(self%contact) == 'frictionless') &
         call append_error(error, "scene: contact = 'frictionless' is not used by integrator = '"// &
                           trim(settings%integrator)//"' (a velocity field per body, whose contact is a non-smooth "// &
                           "constraint the Newton iteration does not take); allowed: contact = 'none', or "// &
                           "integrator = 'explicit'")
      ! the methods that cannot take two bars in contact (docs/theory.md, The cures): the total-Lagrangian
      ! formulation keeps the reference configuration, which contact cannot use; CPDI's domains are one
      ! body's chain of corners; XPIC, FMPM and ASFLIP keep grid fields of one velocity field, not of a
      ! field per bar
      if (trim(settings%formulation) == 'total') &
         call append_error(error, place(given, 'discretisation', 'formulation')//"discretisation: formulation = "// &
                           "'total' is not used by kind = 'impact' (the bars' contact needs their current "// &
                           "configuration; the total-Lagrangian formulation keeps the reference one); allowed: "// &
                           "formulation = 'updated', or another kind")
      if (trim(settings%shape) == 'cpdi') &
         call append_error(error, place(given, 'discretisation', 'shape')//"discretisation: shape = 'cpdi' is not "// &
                           "used by kind = 'impact' (the bars' domains and their contact are not implemented for "// &
                           "CPDI); allowed: another shape, or another kind")
      if (in_list(trim(settings%transfer), 'xpic, fmpm, asflip') .and. trim(self%contact) == 'frictionless') &
         call append_error(error, place(given, 'discretisation', 'transfer')//"discretisation: transfer = '"// &
                           trim(settings%transfer)//"' is not used with contact = 'frictionless' (its grid fields "// &
                           "are of one velocity field, not of a field per bar); allowed: contact = 'none', or "// &
                           "transfer = 'flip', 'pic', 'blend' or 'apic'")
   end subroutine impact_check

   !> The bars' outer ends' motion over the run must fit the grid's automatic margins (at most 1e8 cells).
   subroutine impact_check_run(self, settings, end_time, dx, length_text, error, given)
      class(impact_input_t), intent(in) :: self
      class(settings_t), intent(in) :: settings
      real(dp), intent(in) :: end_time, dx
      character(len=*), intent(in) :: length_text
      type(error_t), allocatable, intent(inout) :: error
      type(parameter_t), intent(in), optional :: given(:)
      real(dp) :: cells
      cells = self%margin_overflow(settings, end_time, dx)
      if (cells == 0.0_dp) return
      call append_error(error, place(given, 'scene', 'velocities')//"scene: velocities = "// &
                        short_number(self%velocities(1))//", "//short_number(self%velocities(2))// &
                        " m/s move the bars' outer ends by up to 1.5 max |v| T = "// &
                        self%margin_overflow_text(end_time, dx, cells, 'margins')//"|velocities| <= "// &
                        num(maxval(abs(self%velocities))*most_margin_cells/cells, 4)//" m/s")
   end subroutine impact_check_run

   !> Both bars and the gap.
   pure real(dp) function impact_length(self)
      class(impact_input_t), intent(in) :: self
      impact_length = sum(self%lengths(1:2)) + self%gap
   end function impact_length

   !> The longer of the bars' wave round trips 2 L/c (identical bars: the contact time).
   pure real(dp) function impact_period(self)
      class(impact_input_t), intent(in) :: self
      impact_period = 2.0_dp*maxval(self%lengths(1:2)/sqrt(self%youngs_moduli(1:2)/self%densities(1:2)))
   end function impact_period

   !> When the bars first touch: gap/(v1 - v2) when bar 1 is faster toward bar 2, else 0 (they touch at
   !> once or never): periods count from then.
   pure real(dp) function contact_time(self)
      class(impact_input_t), intent(in) :: self
      contact_time = 0.0_dp
      if (self%velocity_count /= 2) return
      if (self%velocities(1) > self%velocities(2)) contact_time = self%gap/(self%velocities(1) - self%velocities(2))
   end function contact_time

   !> 1.5 max |v_b| T on either side.
   pure real(dp) function impact_reach(self, end_time)
      class(impact_input_t), intent(in) :: self
      real(dp), intent(in) :: end_time
      impact_reach = 1.5_dp*maxval(abs(self%velocities(1:2)))*end_time
   end function impact_reach

   !> Both bars' outer ends are free.
   pure integer function impact_free_ends(self)
      class(impact_input_t), intent(in) :: self
      impact_free_ends = 2
   end function impact_free_ends

   !> Bars that do not meet before the run ends (end_time given) or never meet: the error measures free
   !> flight, which any scheme follows to round-off.
   function impact_warnings(self, settings) result(text)
      class(impact_input_t), intent(in) :: self
      class(settings_t), intent(in) :: settings
      character(len=:), allocatable :: text
      real(dp) :: meet
      text = ''
      meet = self%periods_from()
      if (self%velocities(1) <= self%velocities(2)) then
         text = "the bars never meet: velocities = "//short_number(self%velocities(1))//", "// &
                short_number(self%velocities(2))//" m/s (bar 1, on the left, is not faster than bar 2); the error "// &
                "measures free flight, not an impact"
      else if (meet >= settings%final_time) then
         text = "the bars do not meet before the end of the run: gap = "//short_number(self%gap)//" m closing at "// &
                num(self%velocities(1) - self%velocities(2), 4)//" m/s first touches at t = "//num(meet, 4)// &
                " s, after the end time "//num(settings%final_time, 4)//" s; the error measures free flight, not "// &
                "the impact (periods count from the first contact; or give a longer end_time)"
      end if
   end function impact_warnings

   !> The run's length counts from the first contact.
   function impact_start_note(self, end_time) result(text)
      class(impact_input_t), intent(in) :: self
      real(dp), intent(in) :: end_time
      character(len=:), allocatable :: text
      text = ''
      if (self%periods_from() > 0.0_dp) &
         text = ": the bars meet at t = gap/(velocities(1) - velocities(2)) = "//num(self%periods_from(), 4)// &
                " s with gap = "//short_number(self%gap)//" m, and periods count from then"
   end function impact_start_note

   subroutine impact_make(self, settings, scene, error)
      class(impact_input_t), intent(in) :: self
      class(settings_t), intent(in) :: settings
      class(scene_t), allocatable, intent(out) :: scene
      type(error_t), allocatable, intent(out) :: error
      allocate (scene, source=impact_init(self, settings))
   end subroutine impact_make

   !> The scene of a validated and resolved configuration.
   pure function impact_init(input, settings) result(scene)
      type(impact_input_t), intent(in) :: input
      class(settings_t), intent(in) :: settings
      type(impact_t) :: scene
      scene%body_fields = trim(input%contact) == 'frictionless'
      scene%stick = .not. scene%body_fields
      scene%watches = .true.
      scene%length = input%lengths(1:2)
      scene%modulus = input%youngs_moduli(1:2)
      scene%density = input%densities(1:2)
      scene%plastic = trim(settings%law) == 'elastoplastic'
      if (scene%plastic) then
         scene%yield_stress = input%yield_stresses(1:2)
         scene%hardening_modulus = input%hardening_moduli(1:2)
      end if
      scene%speed = sqrt(scene%modulus/scene%density)
      scene%velocity = input%velocities(1:2)
      scene%gap = input%gap
      scene%mass = scene%density*scene%length
      scene%dt = settings%dt
      scene%end_time = settings%steps*settings%dt
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
   subroutine place_particles(self, settings, particles, error)
      class(impact_t), intent(in) :: self
      class(settings_t), intent(in) :: settings
      type(particles_t), intent(out) :: particles
      type(error_t), allocatable, intent(out) :: error
      integer :: cells(2), b, k, p, stat, per_bar
      real(dp) :: sub, left
      cells = max(1, nint(self%length/settings%dx))
      call particles_init(particles, sum(cells), settings%particles_per_element, settings%dx, 1.0_dp, error)
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
         per_bar = cells(b)*settings%particles_per_element
         sub = self%length(b)/per_bar
         left = merge(0.0_dp, self%length(1) + self%gap, b == 1)
         do k = 1, per_bar
            p = p + 1
            particles%x(p) = left + (k - 0.5_dp)*sub
            particles%cell(p) = min(int(particles%x(p)/settings%dx) + 1, settings%elements)
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
      class(watch_t), allocatable, intent(inout) :: watch
      real(dp), intent(out) :: error
      real(dp) :: moment, mass, bar1, total, scale, smallest
      type(impact_watch_t) :: start
      if (.not. allocated(watch)) then ! (the first step: the initial momenta)
         start%momentum1 = self%velocity(1)*sum(particles%mass_of, mask=particles%body == 1)
         start%momentum0 = self%velocity(1)*sum(particles%mass_of, mask=particles%body == 1) + &
                           self%velocity(2)*sum(particles%mass_of, mask=particles%body == 2)
         call step_sums(particles, moment, start%mass1, bar1, total) ! (bar 1's mass, as error_at sums it)
         allocate (watch, source=start)
      end if
      select type (w => watch)
      type is (impact_watch_t)
         if (totals%bodies == 2) then ! (each bar a body on stacked fields: body b is bar b)
            moment = totals%body_displacement(1)
            mass = w%mass1
            bar1 = totals%body_momentum(1)
            total = totals%body_momentum(1) + totals%body_momentum(2)
            smallest = totals%min_stress
         else
            call step_sums(particles, moment, mass, bar1, total)
            smallest = smallest_value(particles%stress)
         end if
         error = abs(moment/mass - self%bar1_exact(t))
         scale = sum(self%mass*abs(self%velocity))
         if (abs(bar1 - w%momentum1) > 1.0e-9_dp*scale) then
            w%steps = w%steps + 1.0_dp
            w%first = min(w%first, t - self%dt)
            w%last = t
         end if
         w%momentum1 = bar1
         w%min_stress = min(w%min_stress, smallest)
         w%drift = max(w%drift, abs(total - w%momentum0))
      end select
   end subroutine watch_step

   !> contact_time (steps in contact times dt), contact_start and contact_end, the largest compressive
   !> stress (Pa, positive), each bar's final centre-of-mass velocity, the final total momentum and
   !> its largest change over the run relative to sum_b M_b |v_b|.
   subroutine watch_report(self, watch, particles, names, values)
      class(impact_t), intent(in) :: self
      class(watch_t), allocatable, intent(in) :: watch
      type(particles_t), intent(in) :: particles
      character(len=32), allocatable, intent(out) :: names(:)
      real(dp), allocatable, intent(out) :: values(:)
      real(dp) :: final(2), total, scale
      integer :: b
      names = [character(len=32) :: 'contact_time', 'contact_start', 'contact_end', 'max_compressive_stress', &
               'final_velocity_1', 'final_velocity_2', 'final_momentum', 'momentum_change']
      allocate (values(size(names)))
      values = 0.0_dp
      if (.not. allocated(watch)) return ! (no step done)
      do b = 1, 2
         final(b) = sum(particles%mass_of*particles%v, mask=particles%body == b)/ &
                    sum(particles%mass_of, mask=particles%body == b)
      end do
      total = sum(particles%mass_of*particles%v)
      scale = max(sum(self%mass*abs(self%velocity)), tiny(1.0_dp))
      select type (w => watch)
      type is (impact_watch_t)
         values = [w%steps*self%dt, merge(0.0_dp, w%first, w%steps == 0.0_dp), w%last, -w%min_stress, final(1), &
                   final(2), total, w%drift/scale]
      end select
   end subroutine watch_report
   function impact_amplitude_source(self) result(text)
      class(impact_input_t), intent(in) :: self
      character(len=:), allocatable :: text
      text = 'the velocities'
   end function impact_amplitude_source

   subroutine impact_watch_sync(self, state, name)
      class(impact_watch_t), intent(inout) :: self
      type(state_t), intent(inout) :: state
      character(len=*), intent(in) :: name
      call state%sync(name//'.steps', self%steps)
      call state%sync(name//'.first', self%first)
      call state%sync(name//'.last', self%last)
      call state%sync(name//'.min_stress', self%min_stress)
      call state%sync(name//'.drift', self%drift)
      call state%sync(name//'.momentum1', self%momentum1)
      call state%sync(name//'.momentum0', self%momentum0)
      call state%sync(name//'.mass1', self%mass1)
   end subroutine impact_watch_sync

   subroutine impact_new_watch(self, watch)
      class(impact_t), intent(in) :: self
      class(watch_t), allocatable, intent(out) :: watch
      allocate (impact_watch_t :: watch)
   end subroutine impact_new_watch

end module mpm_scene_impact
