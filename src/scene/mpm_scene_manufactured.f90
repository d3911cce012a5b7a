!> A manufactured solution at large strain (the method of manufactured solutions for MPM:
!> [Wallstedt & Guilkey 2008]; references: docs/theory.md). A bar on [0, L], both ends fixed,
!> moves exactly as
!>   u(X,t) = A sin(k X) sin(w t),  k = 2 pi/L, w = pi c/L, c^2 = E/rho0,
!> in reference coordinates X, under the body force per unit mass that the momentum balance
!> rho0 d2u/dt2 = dP/dX + rho0 b then requires with the code's own law: in 1-D the first Piola stress is
!> the Cauchy stress sigma = E ln F (mpm_material_elastic), F = 1 + du/dX, so
!>   b(X,t) = d2u/dt2 - c^2 d(ln F)/dX = -A w^2 sin(kX) s + c^2 A k^2 sin(kX) s/F,  s = sin(w t),
!>   F = 1 + A k cos(kX) s  (> 0 everywhere when 2 pi A/L < 1: the namelist checks it).
!> With law = 'linear' (sigma = E (J - 1), so dP/dX = E u_XX) the body force is that law's,
!>   b(X,t) = d2u/dt2 - c^2 u_XX = -A w^2 sin(kX) s + c^2 A k^2 sin(kX) s.
!> Initial state: u = 0, unstressed, v(X,0) = A w sin(kX). Each particle gets the force m_p b(X_p, t)
!> at its reference position and the step's start time, mapped to the grid with the step's shape
!> functions (mpm_particle_forces on the generic path; the fused kernels map it in their passes).
!> Error measure: the mass-weighted RMS over the particles of x_p - X_p - u(X_p, t) (m); relative_error
!> divides it by A. u_cm is exactly zero (ucm_exact = 0).
!> b and u are separable in X and t: each particle keeps A sin(kX_p) and A k cos(kX_p), computed once
!> when it is placed (particles%attached), and a step evaluates sin(w t) once, so that
!>   b_p(t) = (A sin(kX_p) s)(-w^2 + c^2 k^2/(1 + (A k cos(kX_p)) s)),  u(X_p, t) = (A sin(kX_p)) s,
!> the same operations in the same order as from the sines of each particle and step (the same bits),
!> with one division per particle and step and no sine or cosine.
module mpm_scene_manufactured
   use mpm_kinds, only: dp, pi
   use mpm_errors, only: error_t, set_error, append_error
   use mpm_strings, only: str, num
   use mpm_settings, only: settings_t
   use mpm_registry, only: parameter_t, real_entry, short_number, place
   use mpm_grid, only: grid_t
   use mpm_particles, only: particles_t, particles_init
   use mpm_shape, only: shape_cache_t
   use mpm_scene, only: scene_t, sine_profile, exact_name_length
   use mpm_particle_forces, only: p2g_particle_forces
   use mpm_scene_input, only: scene_input_t, scene_kind_t, body_input_t, body_representable, refuse_beyond_doubles
   implicit none
   private
   public :: manufactured_t, manufactured_init, manufactured_input_t

   !> The manufactured solution's input: its body and the displacement amplitude A. Its body force makes
   !> the motion exact for an elastic law: it takes no elastoplastic parameters.
   type, extends(body_input_t) :: manufactured_input_t
      real(dp) :: amplitude = 0.025_dp
   contains
      procedure, nopass :: describe => manufactured_describe
      procedure :: entries => manufactured_entries
      procedure :: amplitude_source => manufactured_amplitude_source
      procedure :: material_entries => manufactured_material_entries
      procedure :: check => manufactured_check
      procedure :: period => manufactured_period
      procedure :: free_ends => manufactured_free_ends
      procedure :: check_representable => manufactured_representable
      procedure :: make => manufactured_make
   end type manufactured_input_t

   type, extends(scene_t) :: manufactured_t
      real(dp) :: length = 0.0_dp
      real(dp) :: amplitude = 0.0_dp   !< A (m)
      real(dp) :: density = 0.0_dp
      real(dp) :: wave_speed = 0.0_dp
      real(dp) :: wave_number = 0.0_dp !< k = 2 pi/L (1/m)
      real(dp) :: omega = 0.0_dp       !< w = pi c/L (rad/s)
      integer :: elements = 0          !< the body's elements: node `elements` is the fixed right end
      !> the law is 'linear' (sigma = E (J - 1)): the body force of that law instead of E ln F's
      logical :: linear_law = .false.
   contains
      procedure :: place_particles, margin_cells, fixed_nodes, ucm_exact, ucm_amplitude
      procedure :: add_forces, error_at, error_name, energy_reference, report, fused_applies, particle_forces
      procedure :: displacement_exact, body_force, exact_fields
   end type manufactured_t

   !> The columns of particles%attached: A sin(k X_p), A k cos(k X_p).
   integer, parameter :: factor_sine = 1, factor_cosine = 2

contains

   pure function manufactured_describe() result(kind)
      type(scene_kind_t) :: kind
      kind = scene_kind_t('manufactured', 'a manufactured solution at large strain', '2L/c')
   end function manufactured_describe

   subroutine manufactured_entries(self, table)
      class(manufactured_input_t), intent(inout), target :: self
      type(parameter_t), allocatable, intent(out) :: table(:)
      call self%body_entries(table)
      table = [table, real_entry('scene', 'amplitude', self%amplitude, 'm', 'A of the manufactured displacement '// &
                                 'u(X,t) = A sin(2 pi X/length) sin(pi c t/length)', greater_than=0.0_dp, &
                                 note='2 pi A / length < 1', sweep_list='amplitudes')]
   end subroutine manufactured_entries

   !> No law's parameters: the body force is made for an elastic law.
   subroutine manufactured_material_entries(self, table)
      class(manufactured_input_t), intent(inout), target :: self
      type(parameter_t), allocatable, intent(out) :: table(:)
      allocate (table(0))
   end subroutine manufactured_material_entries

   !> F > 0 everywhere (2 pi A / L < 1), and an elastic law.
   subroutine manufactured_check(self, settings, error, given)
      class(manufactured_input_t), intent(in) :: self
      class(settings_t), intent(in) :: settings
      type(error_t), allocatable, intent(inout) :: error
      type(parameter_t), intent(in), optional :: given(:)
      if (2*pi*self%amplitude >= self%length) call append_error(error, place(given, 'scene', 'amplitude')// &
         "scene: kind = 'manufactured' needs 2 pi amplitude / length < 1 (F > 0 everywhere); amplitude = "// &
         short_number(self%amplitude)//" m, length = "//short_number(self%length)//" m give "// &
         num(2*pi*self%amplitude/self%length, 4)//"; allowed: amplitude < "//num(self%length/(2*pi), 4)//" m")
      if (trim(settings%law) == 'elastoplastic') &
         call append_error(error, "material: law = 'elastoplastic' is not used by kind = 'manufactured' (its body "// &
                           "force makes the motion exact for an elastic law); allowed: law = 'hencky' or 'linear'")
   end subroutine manufactured_check

   !> u oscillates as sin(pi c t/L): period 2L/c.
   pure real(dp) function manufactured_period(self)
      class(manufactured_input_t), intent(in) :: self
      manufactured_period = 2.0_dp*self%length/sqrt(self%youngs_modulus/self%density)
   end function manufactured_period

   !> Both ends are fixed: no automatic margin.
   pure integer function manufactured_free_ends(self)
      class(manufactured_input_t), intent(in) :: self
      manufactured_free_ends = 0
   end function manufactured_free_ends

   !> Beyond the wave speed (body_input_t): the products its body force, energies and error measure form
   !> as they stand within the doubles (compared as logarithms).
   subroutine manufactured_representable(self, settings, error)
      class(manufactured_input_t), intent(in) :: self
      class(settings_t), intent(in) :: settings
      type(error_t), allocatable, intent(inout) :: error
      real(dp) :: log_ratio
      call body_representable(self, settings, error)
      if (allocated(error)) return
      log_ratio = log10(self%youngs_modulus) - log10(self%density)
      call within("(c/L)^2", log_ratio - 2*log10(self%length))
      call within("the body force A (c/L)^2", log10(self%amplitude) + log_ratio - 2*log10(self%length))
      call within("the energy rho (c A)^2/L", log10(self%density) + log_ratio + 2*log10(self%amplitude) - &
                  log10(self%length))
      call within("the error measure's scale rho L (A/100)^2", log10(self%density) + log10(self%length) + &
                  2*log10(self%amplitude) - 4)
   contains
      !> Refuse the scene when a product its formulas form (log10 `magnitude`) leaves the doubles.
      subroutine within(what, magnitude)
         character(len=*), intent(in) :: what
         real(dp), intent(in) :: magnitude
         call refuse_beyond_doubles(error, "kind = "// &
            "'manufactured' with length = "//short_number(self%length)//" m, amplitude = "// &
            short_number(self%amplitude)//" m and youngs_modulus = "//short_number(self%youngs_modulus)// &
            " Pa and density = "//short_number(self%density)//" kg/m^3", what, magnitude)
      end subroutine within
   end subroutine manufactured_representable

   subroutine manufactured_make(self, settings, scene, error)
      class(manufactured_input_t), intent(in) :: self
      class(settings_t), intent(in) :: settings
      class(scene_t), allocatable, intent(out) :: scene
      type(error_t), allocatable, intent(out) :: error
      allocate (scene, source=manufactured_init(self%length, self%youngs_modulus, self%density, self%amplitude, &
                                                settings%elements, settings%law))
   end subroutine manufactured_make

   pure function manufactured_init(length, youngs_modulus, density, amplitude, elements, law) result(scene)
      real(dp), intent(in) :: length, youngs_modulus, density, amplitude
      integer, intent(in) :: elements
      !> the law's name (default 'hencky')
      character(len=*), intent(in), optional :: law
      type(manufactured_t) :: scene
      if (present(law)) scene%linear_law = trim(law) == 'linear'
      scene%external_forces = .true.
      scene%has_particle_forces = .true.
      scene%length = length
      scene%amplitude = amplitude
      scene%density = density
      scene%wave_speed = sqrt(youngs_modulus/density)
      scene%wave_number = 2.0_dp*pi/length
      scene%omega = pi*scene%wave_speed/length
      scene%elements = elements
   end function manufactured_init

   !> u(X, t) = A sin(k X) sin(w t).
   elemental real(dp) function displacement_exact(self, x0, t)
      class(manufactured_t), intent(in) :: self
      real(dp), intent(in) :: x0, t
      displacement_exact = self%amplitude*sin(self%wave_number*x0)*sin(self%omega*t)
   end function displacement_exact

   !> The exact fields at X = x0: u, v = A w sin(k X) cos(w t) and the law's stress of F = 1 + du/dX,
   !> sigma = E ln F (hencky) or E (F - 1) (linear), E = rho0 c^2.
   pure subroutine exact_fields(self, x0, t, names, values)
      class(manufactured_t), intent(in) :: self
      real(dp), intent(in) :: x0(:), t
      character(len=exact_name_length), allocatable, intent(out) :: names(:)
      real(dp), allocatable, intent(out) :: values(:, :)
      real(dp), allocatable :: strain(:)
      names = [character(len=exact_name_length) :: 'displacement', 'velocity', 'stress']
      allocate (values(size(x0), 3))
      values(:, 1) = self%displacement_exact(x0, t)
      values(:, 2) = self%amplitude*self%omega*sin(self%wave_number*x0)*cos(self%omega*t)
      strain = self%amplitude*self%wave_number*cos(self%wave_number*x0)*sin(self%omega*t)
      if (self%linear_law) then
         values(:, 3) = self%density*self%wave_speed**2*strain
      else
         values(:, 3) = self%density*self%wave_speed**2*log(1.0_dp + strain)
      end if
   end subroutine exact_fields

   !> b(X, t) = d2u/dt2 - c^2 d(ln F)/dX, or d2u/dt2 - c^2 u_XX for the linear law (see the module's comment).
   elemental real(dp) function body_force(self, x0, t)
      class(manufactured_t), intent(in) :: self
      real(dp), intent(in) :: x0, t
      real(dp) :: s, sine, f
      s = sin(self%omega*t)
      sine = sin(self%wave_number*x0)
      f = 1.0_dp + self%amplitude*self%wave_number*cos(self%wave_number*x0)*s
      if (self%linear_law) f = 1.0_dp
      body_force = self%amplitude*sine*s*(-self%omega**2 + self%wave_speed**2*self%wave_number**2/f)
   end function body_force

   !> As the bar's particles, with the exact initial velocity A w sin(k X), and each particle's factors
   !> A sin(k X_p), A k cos(k X_p) (see the module's comment): one scalar sine and cosine per particle
   !> (as sine_profile, not vectorised, so that every run starts from the same bits).
   subroutine place_particles(self, settings, particles, error)
      class(manufactured_t), intent(in) :: self
      class(settings_t), intent(in) :: settings
      type(particles_t), intent(out) :: particles
      type(error_t), allocatable, intent(out) :: error
      real(dp) :: amplitude_k
      integer :: p, stat
      call particles_init(particles, settings%elements, settings%particles_per_element, settings%dx, self%density, &
                          error)
      if (allocated(error)) return
      allocate (particles%attached(particles%count, 2), stat=stat)
      if (stat /= 0) then
         call set_error(error, 'cannot allocate the manufactured solution''s factors of '//str(particles%count)// &
                        ' particles (out of memory)')
         return
      end if
      ! sin(k X_p) once: the initial velocity (A w) sin(k X_p), as sine_profile makes it, and A sin(k X_p)
      call sine_profile(1.0_dp, self%wave_number, particles%x0, particles%attached(:, factor_sine))
      particles%v = (self%amplitude*self%omega)*particles%attached(:, factor_sine)
      particles%attached(:, factor_sine) = self%amplitude*particles%attached(:, factor_sine)
      amplitude_k = self%amplitude*self%wave_number
      !GCC$ novector
      do p = 1, particles%count
         particles%attached(p, factor_cosine) = amplitude_k*cos(self%wave_number*particles%x0(p))
      end do
   end subroutine place_particles

   !> Both ends are fixed: no free end, no margin unless asked for.
   pure integer function margin_cells(self, dx, requested) result(cells)
      class(manufactured_t), intent(in) :: self
      real(dp), intent(in) :: dx
      integer, intent(in) :: requested
      cells = max(requested, 0)
   end function margin_cells

   pure function fixed_nodes(self) result(nodes)
      class(manufactured_t), intent(in) :: self
      integer, allocatable :: nodes(:)
      nodes = [0, self%elements]
   end function fixed_nodes

   !> int_0^L sin(k X) dX = 0: the centre of mass stays at rest.
   pure real(dp) function ucm_exact(self, t)
      class(manufactured_t), intent(in) :: self
      real(dp), intent(in) :: t
      ucm_exact = 0.0_dp
   end function ucm_exact

   pure real(dp) function ucm_amplitude(self)
      class(manufactured_t), intent(in) :: self
      ucm_amplitude = self%amplitude
   end function ucm_amplitude

   !> f_I += sum_p N_Ip m_p b(X_p, t) (particle_forces; the scratch array is allocated here: the generic path).
   subroutine add_forces(self, grid, t, cache, particles)
      class(manufactured_t), intent(in) :: self
      type(grid_t), intent(inout) :: grid
      real(dp), intent(in) :: t
      type(shape_cache_t), intent(in) :: cache
      type(particles_t), intent(in) :: particles
      real(dp), allocatable :: forces(:)
      allocate (forces(particles%count))
      call self%particle_forces(t, particles, forces)
      call p2g_particle_forces(cache, forces, grid)
   end subroutine add_forces

   !> m_p b(X_p, t) from the particles' factors (the module's comment): one sine per call; the linear law's
   !> b without F. The mass is the particle's own (mass_of) where it has one, else the run's one mass
   !> (the fused kernels').
   subroutine particle_forces(self, t, particles, forces)
      class(manufactured_t), intent(in) :: self
      real(dp), intent(in) :: t
      type(particles_t), intent(in) :: particles
      real(dp), intent(out), contiguous :: forces(:)
      real(dp) :: s, inertia, stiffness
      s = sin(self%omega*t)
      inertia = -self%omega**2
      stiffness = self%wave_speed**2*self%wave_number**2
      associate (sine => particles%attached(:, factor_sine), cosine => particles%attached(:, factor_cosine))
         if (self%linear_law) then ! (F = 1 in body_force: c^2 k^2 / 1 is c^2 k^2, the same bits)
            if (allocated(particles%mass_of)) then
               forces = particles%mass_of*(sine*s*(inertia + stiffness))
            else
               forces = particles%mass*(sine*s*(inertia + stiffness))
            end if
         else if (allocated(particles%mass_of)) then
            forces = particles%mass_of*(sine*s*(inertia + stiffness/(1.0_dp + cosine*s)))
         else
            forces = particles%mass*(sine*s*(inertia + stiffness/(1.0_dp + cosine*s)))
         end if
      end associate
   end subroutine particle_forces

   !> sqrt(sum_p m_p (x_p - X_p - u(X_p, t))^2 / sum_p m_p) (m), u(X_p, t) = (A sin(k X_p)) sin(w t); the
   !> particles' own masses where they have them, else the run's one mass.
   real(dp) function error_at(self, t, particles, ucm)
      class(manufactured_t), intent(in) :: self
      real(dp), intent(in) :: t, ucm
      type(particles_t), intent(in) :: particles
      real(dp) :: s
      s = sin(self%omega*t)
      associate (sine => particles%attached(:, factor_sine))
         if (allocated(particles%mass_of)) then
            error_at = sqrt(sum(particles%mass_of*(particles%x - particles%x0 - sine*s)**2)/sum(particles%mass_of))
         else
            error_at = sqrt(sum((particles%x - particles%x0 - sine*s)**2)/particles%count)
         end if
      end associate
   end function error_at

   !> The fused kernels take it: one mass, one modulus, the forces mapped in their passes.
   pure logical function fused_applies(self)
      class(manufactured_t), intent(in) :: self
      fused_applies = .true.
   end function fused_applies

   !> The largest strain of the exact motion, max |F - 1| = 2 pi A/L.
   pure subroutine report(self, names, values)
      class(manufactured_t), intent(in) :: self
      character(len=32), allocatable, intent(out) :: names(:)
      real(dp), allocatable, intent(out) :: values(:)
      names = [character(len=32) :: 'max_strain']
      values = [self%amplitude*self%wave_number]
   end subroutine report

   pure function error_name(self) result(name)
      class(manufactured_t), intent(in) :: self
      character(len=:), allocatable :: name
      name = 'mass-weighted RMS of (x_p - X_p - u(X_p,t))'
   end function error_name

   !> The exact motion's largest kinetic plus strain energy, at most rho A^2 pi^2 c^2/(4L) + rho c^2 A^2 pi^2/L.
   pure real(dp) function energy_reference(self, initial_energy)
      class(manufactured_t), intent(in) :: self
      real(dp), intent(in) :: initial_energy
      energy_reference = max(initial_energy, 1.25_dp*self%density*(self%wave_speed*self%amplitude*pi)**2/self%length)
   end function energy_reference
   function manufactured_amplitude_source(self) result(text)
      class(manufactured_input_t), intent(in) :: self
      character(len=:), allocatable :: text
      text = 'amplitude'
   end function manufactured_amplitude_source

end module mpm_scene_manufactured
