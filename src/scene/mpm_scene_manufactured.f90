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
!> functions (mpm_particle_forces). Error measure: the mass-weighted RMS over the particles of
!> x_p - X_p - u(X_p, t) (m); relative_error divides it by A. u_cm is exactly zero (ucm_exact = 0).
module mpm_scene_manufactured
   use mpm_kinds, only: dp, pi
   use mpm_errors, only: error_t
   use mpm_config, only: config_t
   use mpm_grid, only: grid_t
   use mpm_particles, only: particles_t, particles_init
   use mpm_shape, only: shape_cache_t
   use mpm_scene, only: scene_t, sine_profile
   use mpm_particle_forces, only: p2g_particle_forces
   implicit none
   private
   public :: manufactured_t, manufactured_init

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
      procedure :: add_forces, error_at, error_name, energy_reference, report
      procedure :: displacement_exact, body_force
   end type manufactured_t

contains

   pure function manufactured_init(length, youngs_modulus, density, amplitude, elements, law) result(scene)
      real(dp), intent(in) :: length, youngs_modulus, density, amplitude
      integer, intent(in) :: elements
      !> the law's name (default 'hencky')
      character(len=*), intent(in), optional :: law
      type(manufactured_t) :: scene
      if (present(law)) scene%linear_law = trim(law) == 'linear'
      scene%external_forces = .true.
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

   !> As the bar's particles, with the exact initial velocity A w sin(k X).
   subroutine place_particles(self, config, particles, error)
      class(manufactured_t), intent(in) :: self
      type(config_t), intent(in) :: config
      type(particles_t), intent(out) :: particles
      type(error_t), allocatable, intent(out) :: error
      call particles_init(particles, config%elements, config%particles_per_element, config%dx, config%density, error)
      if (allocated(error)) return
      call sine_profile(self%amplitude*self%omega, self%wave_number, particles%x, particles%v)
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

   !> f_I += sum_p N_Ip m_p b(X_p, t).
   subroutine add_forces(self, grid, t, cache, particles)
      class(manufactured_t), intent(in) :: self
      type(grid_t), intent(inout) :: grid
      real(dp), intent(in) :: t
      type(shape_cache_t), intent(in) :: cache
      type(particles_t), intent(in) :: particles
      real(dp), allocatable :: forces(:)
      forces = particles%mass_of*self%body_force(particles%x0, t)
      call p2g_particle_forces(cache, forces, grid)
   end subroutine add_forces

   !> sqrt(sum_p m_p (x_p - X_p - u(X_p, t))^2 / sum_p m_p) (m).
   real(dp) function error_at(self, t, particles, ucm)
      class(manufactured_t), intent(in) :: self
      real(dp), intent(in) :: t, ucm
      type(particles_t), intent(in) :: particles
      error_at = sqrt(sum(particles%mass_of*(particles%x - particles%x0 - self%displacement_exact(particles%x0, t))**2)/ &
                      sum(particles%mass_of))
   end function error_at

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
end module mpm_scene_manufactured
