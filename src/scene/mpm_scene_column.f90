!> A column under its own weight, suddenly loaded: length L on [0, L], fixed at x = 0, free at x = L,
!> at rest and unstressed at t = 0, body force -g per unit mass (towards the fixed end) from t = 0.
!> Exact (linear elasticity, c^2 = E/rho; separation of variables as for the bar, e.g. Graff, Wave
!> Motion in Elastic Solids, 1975, sec. 2.2): u(x,t) = u_s(x) + sum_n a_n sin(beta_n x) cos(omega_n t),
!>   u_s(x) = -(g/c^2)(L x - x^2/2)  (the static solution: u_s(0) = 0, u_s'(L) = 0),
!>   beta_n = (2n-1) pi/(2L), omega_n = beta_n c,
!>   a_n = -(2/L) int_0^L u_s sin(beta_n x) dx = 2 g/(c^2 L beta_n^3)  (u(x,0) = 0).
!> Centre of mass (1/L) int_0^L u dx, with int_0^L sin(beta_n x) dx = 1/beta_n:
!>   u_cm(t) = -g L^2/(3 c^2) + sum_n 2 g/(c^2 L^2 beta_n^4) cos(omega_n t)
!>           = -g L^2/(3 c^2) + (32 g L^2/(pi^4 c^2)) S(omega_1 t),  S(th) = sum_n cos((2n-1) th)/(2n-1)^4,
!> and the series S in closed form (integrating twice sum_n cos((2n-1) th)/(2n-1)^2 = pi(pi - 2|th|)/8,
!> |th| <= pi): S(th) = pi^4/96 - pi (pi th^2/2 - th^3/3)/8 on [0, pi], even and 2 pi-periodic, with
!> S(2 pi - th) = S(th). So u_cm swings between 0 and -2 g L^2/(3 c^2): its amplitude is g L^2/(3 c^2).
!> The sum to round-off and the closed form agree (test_scenes). Needs the external force on the grid:
!> f_I += m_I (-g) (the lumped mass carries sum_p N_Ip m_p (-g) exactly, since sum_I N_Ip = 1).
module mpm_scene_column
   use mpm_kinds, only: dp, pi
   use mpm_errors, only: error_t
   use mpm_config, only: config_t
   use mpm_grid, only: grid_t, grid_loads_t
   use mpm_particles, only: particles_t, particles_init
   use mpm_shape, only: shape_cache_t
   use mpm_particle_forces, only: p2g_particle_forces
   use mpm_scene, only: scene_t, margin_for
   implicit none
   private
   public :: column_t, column_init, column_series

   type, extends(scene_t) :: column_t
      real(dp) :: length = 0.0_dp
      real(dp) :: gravity = 0.0_dp
      real(dp) :: density = 0.0_dp
      real(dp) :: wave_speed = 0.0_dp
      real(dp) :: omega = 0.0_dp      !< omega_1 = pi c/(2L) (rad/s)
      real(dp) :: amplitude = 0.0_dp  !< g L^2/(3 c^2): the u_cm swing's half range and mean offset (m)
   contains
      procedure :: place_particles, margin_cells, fixed_nodes, ucm_exact, ucm_amplitude
      procedure :: add_forces, energy_reference, report, fused_applies, grid_loads
   end type column_t

contains

   pure function column_init(length, youngs_modulus, density, gravity) result(column)
      real(dp), intent(in) :: length, youngs_modulus, density, gravity
      type(column_t) :: column
      column%external_forces = .true.
      column%length = length
      column%gravity = gravity
      column%density = density
      column%wave_speed = sqrt(youngs_modulus/density)
      column%omega = pi*column%wave_speed/(2.0_dp*length)
      column%amplitude = gravity*length**2/(3.0_dp*column%wave_speed**2)
   end function column_init

   !> S(th) = sum_{n>=1} cos((2n-1) th)/(2n-1)^4 in closed form (see the module's comment).
   elemental real(dp) function column_series(theta) result(s)
      real(dp), intent(in) :: theta
      real(dp) :: th
      th = modulo(abs(theta), 2.0_dp*pi)
      if (th > pi) th = 2.0_dp*pi - th
      s = pi**4/96.0_dp - pi*(pi*th**2/2.0_dp - th**3/3.0_dp)/8.0_dp
   end function column_series

   !> As the bar's: `particles_per_element` particles per element at the centres of equal sub-cells, at rest.
   subroutine place_particles(self, config, particles, error)
      class(column_t), intent(in) :: self
      type(config_t), intent(in) :: config
      type(particles_t), intent(out) :: particles
      type(error_t), allocatable, intent(out) :: error
      call particles_init(particles, config%elements, config%particles_per_element, config%dx, config%density, error)
   end subroutine place_particles

   !> The free end moves towards the fixed one, by at most twice the static end displacement g L^2/(2 c^2)
   !> (the grid's span is enough); two cells beyond it for the shape support and slack, as the bar,
   !> plus the end's excursion in cells should gravity ever point the other way.
   pure integer function margin_cells(self, dx, requested) result(cells)
      class(column_t), intent(in) :: self
      real(dp), intent(in) :: dx
      integer, intent(in) :: requested
      cells = margin_for(abs(self%gravity)*self%length**2/self%wave_speed**2, dx, requested)
   end function margin_cells

   pure function fixed_nodes(self) result(nodes)
      class(column_t), intent(in) :: self
      integer, allocatable :: nodes(:)
      nodes = [0]
   end function fixed_nodes

   pure real(dp) function ucm_exact(self, t)
      class(column_t), intent(in) :: self
      real(dp), intent(in) :: t
      ucm_exact = -self%amplitude + 32.0_dp*self%gravity*self%length**2/(pi**4*self%wave_speed**2)* &
                  column_series(self%omega*t)
   end function ucm_exact

   pure real(dp) function ucm_amplitude(self)
      class(column_t), intent(in) :: self
      ucm_amplitude = self%amplitude
   end function ucm_amplitude

   !> Gravity: f_I += m_I (-g) on every node (the fixed node's force is cleared by the grid solve).
   subroutine add_forces(self, grid, t, cache, particles)
      class(column_t), intent(in) :: self
      type(grid_t), intent(inout) :: grid
      real(dp), intent(in) :: t
      type(shape_cache_t), intent(in) :: cache
      type(particles_t), intent(in) :: particles
      if (grid%mirror) then
         ! the nodal masses hold the mirror image's too (mpm_operations, mirror_fold): the weight of
         ! the column's own particles, sum_p N_Ip m_p (-g), which the scheme reflects with the
         ! internal force
         call p2g_particle_forces(cache, -self%gravity*particles%mass_of, grid)
      else
         grid%force = grid%force - self%gravity*grid%mass  ! = sum_p N_Ip m_p (-g): partition of unity
      end if
   end subroutine add_forces

   !> The fused kernels take the column: its weight is a grid load (grid_loads).
   pure logical function fused_applies(self)
      class(column_t), intent(in) :: self
      fused_applies = .true.
   end function fused_applies

   !> Gravity as a uniform body acceleration -g: f_I += m_I (-g) where the fused kernels assemble the
   !> nodal force, before a mirror's fold (the nodal masses are then the column's own), as add_forces.
   pure function grid_loads(self) result(loads)
      class(column_t), intent(in) :: self
      type(grid_loads_t) :: loads
      loads%acceleration = -self%gravity
   end function grid_loads

   !> The static end displacement u_s(L) = -g L^2/(2 c^2) (m), about which the free end oscillates.
   pure subroutine report(self, names, values)
      class(column_t), intent(in) :: self
      character(len=32), allocatable, intent(out) :: names(:)
      real(dp), allocatable, intent(out) :: values(:)
      names = [character(len=32) :: 'static_end_displacement']
      values = [-self%gravity*self%length**2/(2.0_dp*self%wave_speed**2)]
   end subroutine report

   !> The largest kinetic + strain energy of the exact motion: gravity's work down to u = 2 u_s,
   !> rho g int_0^L 2|u_s| dx = 2 rho g^2 L^3/(3 c^2) (it is all strain energy there).
   pure real(dp) function energy_reference(self, initial_energy)
      class(column_t), intent(in) :: self
      real(dp), intent(in) :: initial_energy
      energy_reference = max(initial_energy, 2.0_dp*self%density*self%gravity**2*self%length**3/ &
                             (3.0_dp*self%wave_speed**2), tiny(1.0_dp))
   end function energy_reference
end module mpm_scene_column
