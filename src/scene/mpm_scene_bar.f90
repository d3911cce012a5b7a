!> The axially vibrating bar ([Bardenhagen 2002]; eqs. 11-14 of [Ferreira et al.], the founding paper;
!> references: docs/theory.md): fixed at x = 0,
!> free at x = L, u(x,0) = 0, v(x,0) = v0 sin(beta_n x), beta_n = (2n-1) pi / (2L), omega_n = beta_n c.
!> Exact: u(x,t) = v0/omega_n sin(omega_n t) sin(beta_n x); centre of mass
!> u_cm(t) = (1/L) int_0^L u dx = v0/(omega_n beta_n L) sin(omega_n t)  (cos(beta_n L) = 0 for every n).
!> One body of one material, no external force: the fused kernels apply.
module mpm_scene_bar
   use, intrinsic :: ieee_arithmetic, only: ieee_is_normal, ieee_is_finite
   use mpm_kinds, only: dp, pi
   use mpm_errors, only: error_t
   use mpm_config, only: config_t
   use mpm_particles, only: particles_t, particles_init
   use mpm_scene, only: scene_t, sine_profile, margin_for, exact_name_length
   implicit none
   private
   public :: bar_t, bar_init

   type, extends(scene_t) :: bar_t
      real(dp) :: length = 0.0_dp
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

   pure function bar_init(length, youngs_modulus, density, velocity_amplitude, mode) result(bar)
      real(dp), intent(in) :: length, youngs_modulus, density, velocity_amplitude
      integer, intent(in) :: mode
      type(bar_t) :: bar
      bar%length = length
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
   subroutine place_particles(self, config, particles, error)
      class(bar_t), intent(in) :: self
      type(config_t), intent(in) :: config
      type(particles_t), intent(out) :: particles
      type(error_t), allocatable, intent(out) :: error
      call particles_init(particles, config%elements, config%particles_per_element, config%dx, config%density, error)
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
end module mpm_scene_bar
