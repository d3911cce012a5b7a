!> The axially vibrating bar ([Bardenhagen 2002]; eqs. 11-14 of [Ferreira et al.], the founding paper;
!> references: docs/theory.md): fixed at x = 0,
!> free at x = L, u(x,0) = 0, v(x,0) = v0 sin(beta_n x), beta_n = (2n-1) pi / (2L), omega_n = beta_n c.
!> Exact: u(x,t) = v0/omega_n sin(omega_n t) sin(beta_n x); centre of mass
!> u_cm(t) = (1/L) int_0^L u dx = v0/(omega_n beta_n L) sin(omega_n t)  (cos(beta_n L) = 0 for every n).
!> One body of one material, no external force: the fused kernels apply.
module mpm_scene_bar
   use, intrinsic :: ieee_arithmetic, only: ieee_is_normal, ieee_is_finite
   use mpm_kinds, only: dp, pi, i8
   use mpm_errors, only: error_t, append_error
   use mpm_strings, only: str, num, num_at_least, plural
   use mpm_settings, only: settings_t
   use mpm_registry, only: parameter_t, real_entry, int_entry, short_number, place
   use mpm_particles, only: particles_t, particles_init
   use mpm_scene, only: scene_t, sine_profile, margin_for, exact_name_length
   use mpm_scene_input, only: scene_input_t, scene_kind_t, body_input_t, body_representable
   implicit none
   private
   public :: bar_t, bar_init, bar_input_t

   !> Largest mode: 2 mode - 1 (in beta_n) must be a default integer.
   integer, parameter :: max_mode = (huge(1) - 1)/2
   !> Fewest elements per wavelength of the mode before a run is warned (two resolve a wave at best).
   integer, parameter :: min_elements_per_wavelength = 2

   !> The bar's input: its body, the initial velocity's amplitude v0 and mode n.
   type, extends(body_input_t) :: bar_input_t
      real(dp) :: velocity_amplitude = 0.1_dp
      integer :: mode = 1
   contains
      procedure, nopass :: describe => bar_describe
      procedure :: entries => bar_entries
      procedure :: amplitude_source => bar_amplitude_source
      procedure :: period => bar_period
      procedure :: end_time => bar_end_time
      procedure :: reach => bar_reach
      procedure :: check_representable => bar_representable
      procedure :: short_run => bar_short_run
      procedure :: warnings => bar_warnings
      procedure :: make => bar_make
   end type bar_input_t

   type, extends(scene_t) :: bar_t
      real(dp) :: length = 0.0_dp
      real(dp) :: density = 0.0_dp
      real(dp) :: velocity_amplitude = 0.0_dp
      real(dp) :: wave_speed = 0.0_dp
      real(dp) :: youngs_modulus = 0.0_dp
      integer :: mode = 1
      real(dp) :: beta = 0.0_dp   !< wave number beta_n (1/m)
      real(dp) :: omega = 0.0_dp  !< angular frequency omega_n (rad/s)
      real(dp) :: amplitude = 0.0_dp !< exact u_cm amplitude v0/(omega beta L) (m)
   contains
      procedure :: place_particles, margin_cells, fixed_nodes, ucm_exact, ucm_amplitude, fused_applies
      procedure :: velocity_exact, exact_fields
   end type bar_t

contains

   pure function bar_describe() result(kind)
      type(scene_kind_t) :: kind
      kind = scene_kind_t('vibrating_bar', 'the vibrating bar of the founding study', '2 pi/omega_n (its mode n)')
   end function bar_describe

   subroutine bar_entries(self, table)
      class(bar_input_t), intent(inout), target :: self
      type(parameter_t), allocatable, intent(out) :: table(:)
      call self%body_entries(table)
      table = [table, real_entry('scene', 'velocity_amplitude', self%velocity_amplitude, 'm/s', 'v0 of the '// &
                                 'initial velocity v(x,0) = v0 sin(beta_n x), beta_n = (2n-1) pi / (2 length)', &
                                 sweep_list='velocity_amplitudes'), &
               int_entry('scene', 'mode', self%mode, 'the mode n of the initial velocity', at_least=1, &
                         at_most=max_mode, sweep_list='modes')]
   end subroutine bar_entries

   !> The period of mode n, 2 pi/omega_n.
   pure real(dp) function bar_period(self)
      class(bar_input_t), intent(in) :: self
      bar_period = 2.0_dp*pi/((2*self%mode - 1)*pi/(2.0_dp*self%length)*sqrt(self%youngs_modulus/self%density))
   end function bar_period

   !> periods 2 pi/omega_n, in this association: the paper's step counts.
   real(dp) function bar_end_time(self, settings)
      class(bar_input_t), intent(in) :: self
      class(settings_t), intent(in) :: settings
      real(dp) :: omega
      omega = (2*self%mode - 1)*pi/(2.0_dp*self%length)*sqrt(self%youngs_modulus/self%density)
      bar_end_time = settings%periods*2.0_dp*pi/omega
   end function bar_end_time

   !> The free end's amplitude |v0|/omega_n.
   pure real(dp) function bar_reach(self, end_time)
      class(bar_input_t), intent(in) :: self
      real(dp), intent(in) :: end_time
      bar_reach = abs(self%velocity_amplitude)/((2*real(self%mode, dp) - 1)*pi/(2.0_dp*self%length)*self%wave_speed())
   end function bar_reach

   !> Beyond the wave speed (body_input_t): the free end's motion in cells (the grid's margin must hold
   !> it: at most 1e8 cells), its displacements (normal doubles), the energy rho v0^2 L/4 and the stress
   !> amplitude sqrt(E rho) |v0| (finite doubles). |v0| >= c is allowed (studies/stability runs v0 = c on
   !> purpose; the guards stop such a run). Magnitudes are compared as logarithms.
   subroutine bar_representable(self, settings, error)
      class(bar_input_t), intent(in) :: self
      class(settings_t), intent(in) :: settings
      type(error_t), allocatable, intent(inout) :: error
      real(dp), parameter :: top = log10(huge(1.0_dp)), bottom = log10(tiny(1.0_dp))
      real(dp) :: log_ratio, log_c, log_v, log_cells
      call body_representable(self, settings, error)
      if (allocated(error)) return
      if (self%velocity_amplitude == 0.0_dp) return
      log_ratio = log10(self%youngs_modulus) - log10(self%density)
      log_c = log_ratio/2
      log_v = log10(abs(self%velocity_amplitude))
      ! the free end's amplitude in cells, |v0|/c 2 elements/((2 mode - 1) pi): the grid's margin holds it
      log_cells = log_v - log_c + log10(2*real(settings%elements, dp)/((2*real(self%mode, dp) - 1)*pi))
      if (log_cells > 8 .and. settings%margin_cells < 0) then
         call append_error(error, "scene: velocity_amplitude = "//short_number(self%velocity_amplitude)// &
                           " m/s moves the free end by about 1e"//str(nint(log_cells))//" cells (|v0|/c = 1e"// &
                           str(nint(log_v - log_c))//" with c = sqrt(youngs_modulus/density) = "// &
                           short_number(10.0_dp**log_c)//" m/s); allowed: an amplitude of at most 1e8 cells, "// &
                           "|velocity_amplitude| <= "//short_number(10.0_dp**(log_c + 8 - log_cells + log_v))//" m/s")
      else if (log_v - log_c + log10(self%length) < bottom + 1) then
         ! the exact u_cm amplitude v0/(omega beta L) = (v0/c) L (2/((2n-1) pi))^2 must be a normal double
         call append_error(error, "scene: velocity_amplitude = "//short_number(self%velocity_amplitude)// &
                           " m/s, length = "//short_number(self%length)//" m and "//material()//" give "// &
                           "displacements of about (v0/c) L = 1e"//str(nint(log_v - log_c + log10(self%length)))// &
                           " m, below the doubles (2.2e-307); allowed: a larger velocity_amplitude or length")
      else if (log10(self%density) + 2*log_v + log10(self%length) - log10(4.0_dp) > top - 1) then
         call append_error(error, "scene: density = "//short_number(self%density)//" kg/m^3, velocity_amplitude"// &
                           " = "//short_number(self%velocity_amplitude)//" m/s and length = "// &
                           short_number(self%length)//" m give an energy rho v0^2 L/4 of 1e"// &
                           str(nint(log10(self%density) + 2*log_v + log10(self%length) - log10(4.0_dp)))// &
                           " J/m^2, beyond the doubles; allowed: rho v0^2 L/4 < 1.8e307")
      else if ((log10(self%youngs_modulus) + log10(self%density))/2 + log_v > top - 1) then
         call append_error(error, "scene: "//material()//" with velocity_amplitude = "// &
                           short_number(self%velocity_amplitude)//" m/s give a stress amplitude sqrt(E rho) |v0| "// &
                           "beyond the doubles; allowed: sqrt(youngs_modulus density) |velocity_amplitude| < 1.8e307 Pa")
      end if
   contains
      !> The material's values, for a message (formed only then).
      function material() result(text)
         character(len=:), allocatable :: text
         text = "youngs_modulus = "//short_number(self%youngs_modulus)//" Pa and density = "// &
                short_number(self%density)//" kg/m^3"
      end function material
   end subroutine bar_representable

   !> A mode so high that `periods` of it are shorter than one step: the mode is the cause.
   function bar_short_run(self, settings, end_time, dt, given) result(text)
      class(bar_input_t), intent(in) :: self
      class(settings_t), intent(in) :: settings
      real(dp), intent(in) :: end_time, dt
      type(parameter_t), intent(in), optional :: given(:)
      character(len=:), allocatable :: text
      integer(i8) :: largest_mode
      text = ''
      if (self%mode <= 1) return
      ! periods (2 pi/omega_n = 4 L/((2n-1) c)) >= dt  <=>  2n - 1 <= periods 4 L/(c dt)
      largest_mode = int(min((settings%periods*4*self%length/(self%wave_speed()*dt) + 1)/2, &
                             real(huge(1), dp)), i8)
      text = place(given, 'scene', 'mode')//"scene: mode = "//str(self%mode)//" with periods = "// &
             short_number(settings%periods)//" gives an end time "//num(end_time, 4)//" s, shorter than one "// &
             "time step dt = "//num(dt, 4)//" s; allowed: mode <= "//str(largest_mode)//" (or run: periods >= "// &
             num_at_least(dt/(end_time/settings%periods), 4)//")"
   end function bar_short_run

   !> A mesh with fewer than min_elements_per_wavelength elements per wavelength 4 L/(2 mode - 1).
   function bar_warnings(self, settings) result(text)
      class(bar_input_t), intent(in) :: self
      class(settings_t), intent(in) :: settings
      character(len=:), allocatable :: text
      real(dp) :: per_wavelength
      text = ''
      per_wavelength = 4*real(settings%elements, dp)/(2*real(self%mode, dp) - 1)
      if (per_wavelength < min_elements_per_wavelength) &
         text = 'mode '//str(self%mode)//' has '//num(per_wavelength, 3)//' elements per wavelength on '// &
                plural(settings%elements, 'element')//' (wavelength 4 L/(2 mode - 1)): with fewer than '// &
                str(min_elements_per_wavelength)//' elements per wavelength the mesh cannot represent it, and the '// &
                'error says little about the method'
   end function bar_warnings

   subroutine bar_make(self, settings, scene, error)
      class(bar_input_t), intent(in) :: self
      class(settings_t), intent(in) :: settings
      class(scene_t), allocatable, intent(out) :: scene
      type(error_t), allocatable, intent(out) :: error
      allocate (scene, source=bar_init(self%length, self%youngs_modulus, self%density, self%velocity_amplitude, &
                                       self%mode))
   end subroutine bar_make

   pure function bar_init(length, youngs_modulus, density, velocity_amplitude, mode) result(bar)
      real(dp), intent(in) :: length, youngs_modulus, density, velocity_amplitude
      integer, intent(in) :: mode
      type(bar_t) :: bar
      bar%length = length
      bar%density = density
      bar%velocity_amplitude = velocity_amplitude
      bar%wave_speed = sqrt(youngs_modulus/density)
      bar%youngs_modulus = youngs_modulus
      bar%mode = mode
      bar%beta = (2*mode - 1)*pi/(2.0_dp*length)
      bar%omega = bar%beta*bar%wave_speed
      bar%amplitude = velocity_amplitude/(bar%omega*bar%beta*length)
      ! omega beta L = beta^2 c L leaves the doubles for L far from 1 (1e160: subnormal, 1e-160: overflow)
      ! though the amplitude v0/omega / (beta L), beta L = (2n-1) pi/2, is representable: then that form
      if (.not. (ieee_is_normal(bar%omega*bar%beta) .and. ieee_is_normal(bar%omega*bar%beta*length) .and. &
                 ieee_is_finite(bar%amplitude))) &
         bar%amplitude = velocity_amplitude/bar%omega/((2*mode - 1)*pi/2.0_dp)
   end function bar_init

   !> `particles_per_element` particles per element at the centres of equal sub-cells, unstressed,
   !> with the initial velocity v0 sin(beta x_p).
   subroutine place_particles(self, settings, particles, error)
      class(bar_t), intent(in) :: self
      class(settings_t), intent(in) :: settings
      type(particles_t), intent(out) :: particles
      type(error_t), allocatable, intent(out) :: error
      call particles_init(particles, settings%elements, settings%particles_per_element, settings%dx, self%density, error)
      if (allocated(error)) return
      call sine_profile(self%velocity_amplitude, self%beta, particles%x, particles%v)
   end subroutine place_particles

   !> Empty grid cells beyond the free end x = L: the end's exact displacement amplitude |v0|/omega_n
   !> (sin(beta_n L) = +-1) in cells of size dx, rounded up, plus two cells (one for the particle's
   !> shape support, one of slack), unless `requested` >= 0 gives the number.
   pure integer function margin_cells(self, dx, requested) result(cells)
      class(bar_t), intent(in) :: self
      real(dp), intent(in) :: dx
      integer, intent(in) :: requested
      cells = margin_for(abs(self%velocity_amplitude)/self%omega, dx, requested)
   end function margin_cells

   !> The bar's boundary condition: node 0 (x = 0) is held at rest.
   pure function fixed_nodes(self) result(nodes)
      class(bar_t), intent(in) :: self
      integer, allocatable :: nodes(:)
      nodes = [0]
   end function fixed_nodes

   !> Exact centre-of-mass displacement at time t (eq. 14, any mode).
   pure real(dp) function ucm_exact(self, t)
      class(bar_t), intent(in) :: self
      real(dp), intent(in) :: t
      ucm_exact = self%amplitude*sin(self%omega*t)
   end function ucm_exact

   pure real(dp) function ucm_amplitude(self)
      class(bar_t), intent(in) :: self
      ucm_amplitude = self%amplitude
   end function ucm_amplitude

   pure logical function fused_applies(self)
      class(bar_t), intent(in) :: self
      fused_applies = .true.
   end function fused_applies

   !> Exact velocity field v(x, t) (eq. 13).
   elemental real(dp) function velocity_exact(self, x, t)
      class(bar_t), intent(in) :: self
      real(dp), intent(in) :: x, t
      velocity_exact = self%velocity_amplitude*cos(self%omega*t)*sin(self%beta*x)
   end function velocity_exact

   !> The exact fields of linear elasticity at x0: u = v0/omega_n sin(omega_n t) sin(beta_n x0), v (eq. 13),
   !> sigma = E du/dx = E v0 beta_n/omega_n sin(omega_n t) cos(beta_n x0).
   pure subroutine exact_fields(self, x0, t, names, values)
      class(bar_t), intent(in) :: self
      real(dp), intent(in) :: x0(:), t
      character(len=exact_name_length), allocatable, intent(out) :: names(:)
      real(dp), allocatable, intent(out) :: values(:, :)
      names = [character(len=exact_name_length) :: 'displacement', 'velocity', 'stress']
      allocate (values(size(x0), 3))
      values(:, 1) = self%velocity_amplitude/self%omega*sin(self%omega*t)*sin(self%beta*x0)
      values(:, 2) = self%velocity_exact(x0, t)
      values(:, 3) = self%youngs_modulus*self%velocity_amplitude*self%beta/self%omega*sin(self%omega*t)* &
                     cos(self%beta*x0)
   end subroutine exact_fields
   function bar_amplitude_source(self) result(text)
      class(bar_input_t), intent(in) :: self
      character(len=:), allocatable :: text
      text = 'velocity_amplitude'
   end function bar_amplitude_source

end module mpm_scene_bar
