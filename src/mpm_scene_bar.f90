!> The axially vibrating bar (Bardenhagen 2002; eqs. 11-14 of the founding paper): fixed at x = 0,
!> free at x = L, u(x,0) = 0, v(x,0) = v0 sin(beta_n x), beta_n = (2n-1) pi / (2L), omega_n = beta_n c.
!> Exact: u(x,t) = v0/omega_n sin(omega_n t) sin(beta_n x); centre of mass
!> u_cm(t) = (1/L) int_0^L u dx = v0/(omega_n beta_n L) sin(omega_n t)  (cos(beta_n L) = 0 for every n).
module mpm_scene_bar
   use mpm_kinds, only: dp, pi
   use mpm_particles, only: particles_t
   implicit none
   private
   public :: bar_t, bar_init, bar_initial_velocity, bar_ucm_exact, bar_velocity_exact, bar_margin_cells, bar_fixed_nodes

   type :: bar_t
      real(dp) :: length = 0.0_dp
      real(dp) :: velocity_amplitude = 0.0_dp
      real(dp) :: wave_speed = 0.0_dp
      integer :: mode = 1
      real(dp) :: beta = 0.0_dp   !< wave number beta_n (1/m)
      real(dp) :: omega = 0.0_dp  !< angular frequency omega_n (rad/s)
      real(dp) :: ucm_amplitude = 0.0_dp !< v0/(omega beta L) (m)
   end type bar_t

contains

   pure function bar_init(length, youngs_modulus, density, velocity_amplitude, mode) result(bar)
      real(dp), intent(in) :: length, youngs_modulus, density, velocity_amplitude
      integer, intent(in) :: mode
      type(bar_t) :: bar
      bar%length = length
      bar%velocity_amplitude = velocity_amplitude
      bar%wave_speed = sqrt(youngs_modulus/density)
      bar%mode = mode
      bar%beta = (2*mode - 1)*pi/(2.0_dp*length)
      bar%omega = bar%beta*bar%wave_speed
      bar%ucm_amplitude = velocity_amplitude/(bar%omega*bar%beta*length)
   end function bar_init

   !> Give every particle the initial velocity v0 sin(beta x_p).
   subroutine bar_initial_velocity(bar, particles)
      type(bar_t), intent(in) :: bar
      type(particles_t), intent(inout) :: particles
      particles%v = bar%velocity_amplitude*sin(bar%beta*particles%x)
   end subroutine bar_initial_velocity

   !> Exact centre-of-mass displacement at time t (eq. 14, any mode).
   elemental real(dp) function bar_ucm_exact(bar, t)
      type(bar_t), intent(in) :: bar
      real(dp), intent(in) :: t
      bar_ucm_exact = bar%ucm_amplitude*sin(bar%omega*t)
   end function bar_ucm_exact

   !> Empty grid cells beyond the free end x = L: the end's exact displacement amplitude |v0|/omega_n
   !> (sin(beta_n L) = +-1) in cells of size dx, rounded up, plus two cells (one for the particle's
   !> shape support, one of slack), unless `requested` >= 0 gives the number.
   pure integer function bar_margin_cells(bar, dx, requested) result(cells)
      type(bar_t), intent(in) :: bar
      real(dp), intent(in) :: dx
      integer, intent(in) :: requested
      real(dp) :: reach
      if (requested >= 0) then
         cells = requested
         return
      end if
      reach = abs(bar%velocity_amplitude)/bar%omega/dx
      cells = 2 + int(min(ceiling(reach), 1000000000))
   end function bar_margin_cells

   !> The bar's boundary condition: node 0 (x = 0) is held at rest.
   pure function bar_fixed_nodes() result(nodes)
      integer, allocatable :: nodes(:)
      nodes = [0]
   end function bar_fixed_nodes

   !> Exact velocity field v(x, t) (eq. 13).
   elemental real(dp) function bar_velocity_exact(bar, x, t)
      type(bar_t), intent(in) :: bar
      real(dp), intent(in) :: x, t
      bar_velocity_exact = bar%velocity_amplitude*cos(bar%omega*t)*sin(bar%beta*x)
   end function bar_velocity_exact
end module mpm_scene_bar
