!> The generic operations an MPM step is made of, for any shape function (through shape_cache_t),
!> per-particle masses and volumes, the scene's boundary conditions and forces:
!>   P2G:   m_I = sum_p N_Ip m_p,  p_I = sum_p N_Ip m_p v_p,  f_I = -sum_p dN_Ip sigma_p V_p
!>   solve: p_I += dt f_I,  a_I = f_I/m_I,  v_I = p_I/m_I  (empty nodes: 0; fixed nodes held)
!>   G2P:   v_p += dt sum_I N_Ip a_I (FLIP),  x_p += dt sum_I N_Ip v_I
!>   stress: d eps_p = dt sum_I dN_Ip v_I, then the material update (mpm_material_elastic)
!> Each is one loop over the particles (or nodes), serial: sweeps run cases on threads, and a run's
!> results are the same on any number of threads. The schemes (mpm_scheme_usf/usl/musl) compose them.
module mpm_operations
   use mpm_kinds, only: dp
   use mpm_grid, only: grid_t
   use mpm_particles, only: particles_t
   use mpm_shape, only: shape_cache_t, evaluate_shapes
   use mpm_diagnostics, only: pass_totals_t
   use mpm_material_elastic, only: elastic_update, strain_energy_density
   implicit none
   private
   public :: locate_particles, p2g_mass_momentum, p2g_internal_force, nodal_velocities, solve_grid, g2p, &
             update_stress, particle_energies

contains

   !> Shape functions at the start-of-step positions; totals%outside = first particle outside the domain.
   subroutine locate_particles(cache, grid, particles, totals)
      type(shape_cache_t), intent(inout) :: cache
      type(grid_t), intent(in) :: grid
      type(particles_t), intent(in) :: particles
      type(pass_totals_t), intent(inout) :: totals
      integer :: outside
      call evaluate_shapes(cache, grid, particles%x, outside)
      if (totals%outside == 0) totals%outside = outside
   end subroutine locate_particles

   !> m_I and p_I from the particles (grid fields cleared first).
   subroutine p2g_mass_momentum(cache, particles, grid)
      type(shape_cache_t), intent(in) :: cache
      type(particles_t), intent(in) :: particles
      type(grid_t), intent(inout) :: grid
      integer :: p, k, i
      real(dp) :: wm
      grid%mass = 0.0_dp
      grid%momentum = 0.0_dp
      do p = 1, particles%count
         do k = 1, cache%support
            i = cache%first(p) + k - 1
            if (i < 0) cycle
            wm = cache%weight(k, p)*particles%mass_of(p)
            grid%mass(i) = grid%mass(i) + wm
            grid%momentum(i) = grid%momentum(i) + wm*particles%v(p)
         end do
      end do
   end subroutine p2g_mass_momentum

   !> f_I = -sum_p dN_Ip sigma_p V_p, V_p = J_p V0_p (grid force cleared first).
   subroutine p2g_internal_force(cache, particles, grid)
      type(shape_cache_t), intent(in) :: cache
      type(particles_t), intent(in) :: particles
      type(grid_t), intent(inout) :: grid
      integer :: p, k, i
      real(dp) :: sv
      grid%force = 0.0_dp
      do p = 1, particles%count
         sv = particles%stress(p)*particles%volume_ratio(p)*particles%volume0_of(p)
         do k = 1, cache%support
            i = cache%first(p) + k - 1
            if (i < 0) cycle
            grid%force(i) = grid%force(i) - cache%gradient(k, p)*sv
         end do
      end do
   end subroutine p2g_internal_force

   !> v_I = p_I / m_I (zero on empty nodes), fixed nodes held at rest (momentum and velocity zero).
   subroutine nodal_velocities(grid)
      type(grid_t), intent(inout) :: grid
      where (grid%mass > grid%empty_mass)
         grid%velocity = grid%momentum/grid%mass
      elsewhere
         grid%velocity = 0.0_dp
      end where
      grid%momentum(grid%fixed) = 0.0_dp
      grid%velocity(grid%fixed) = 0.0_dp
   end subroutine nodal_velocities

   !> Explicit momentum update with the assembled force: p_I += dt f_I, a_I = f_I/m_I, v_I = p_I/m_I
   !> (empty nodes 0), fixed nodes held; grid%min_node_mass = the lightest node with mass.
   subroutine solve_grid(grid, dt)
      type(grid_t), intent(inout) :: grid
      real(dp), intent(in) :: dt
      integer :: i
      grid%force(grid%fixed) = 0.0_dp
      grid%momentum(grid%fixed) = 0.0_dp
      grid%min_node_mass = huge(1.0_dp)
      do i = 0, grid%elements
         if (grid%mass(i) > 0.0_dp) grid%min_node_mass = min(grid%min_node_mass, grid%mass(i))
         grid%momentum(i) = grid%momentum(i) + dt*grid%force(i)
         if (grid%mass(i) > grid%empty_mass) then
            grid%acceleration(i) = grid%force(i)/grid%mass(i)
            grid%velocity(i) = grid%momentum(i)/grid%mass(i)
         else
            grid%acceleration(i) = 0.0_dp
            grid%velocity(i) = 0.0_dp
         end if
      end do
      grid%acceleration(grid%fixed) = 0.0_dp
      grid%velocity(grid%fixed) = 0.0_dp
   end subroutine solve_grid

   !> FLIP update of velocity and position with the start-of-step shape functions; totals: sum m (x - X),
   !> kinetic energy, the largest move (cells) and its particle, the first particle outside the domain.
   subroutine g2p(cache, particles, grid, dt, totals)
      type(shape_cache_t), intent(in) :: cache
      type(particles_t), intent(inout) :: particles
      type(grid_t), intent(in) :: grid
      real(dp), intent(in) :: dt
      type(pass_totals_t), intent(inout) :: totals
      integer :: p, k, i
      real(dp) :: a, v, move, lo, hi
      lo = grid%origin
      hi = grid%origin + grid%length
      totals%displacement = 0.0_dp
      totals%kinetic_energy = 0.0_dp
      totals%max_cell_move = 0.0_dp
      totals%furthest = 0
      do p = 1, particles%count
         a = 0.0_dp
         v = 0.0_dp
         do k = 1, cache%support
            i = cache%first(p) + k - 1
            if (i < 0) cycle
            a = a + cache%weight(k, p)*grid%acceleration(i)
            v = v + cache%weight(k, p)*grid%velocity(i)
         end do
         particles%v(p) = particles%v(p) + dt*a
         particles%x(p) = particles%x(p) + dt*v
         move = abs(dt*v)*grid%inv_dx
         if (move > totals%max_cell_move) then
            totals%max_cell_move = move
            totals%furthest = p
         end if
         if (.not. (particles%x(p) >= lo .and. particles%x(p) <= hi) .and. totals%outside == 0) totals%outside = p
         totals%displacement = totals%displacement + particles%mass_of(p)*(particles%x(p) - particles%x0(p))
         totals%kinetic_energy = totals%kinetic_energy + 0.5_dp*particles%mass_of(p)*particles%v(p)**2
      end do
   end subroutine g2p

   !> Strain increment d eps = dt sum_I dN_Ip v_I and the material update; totals: strain energy, min J.
   subroutine update_stress(cache, particles, grid, dt, youngs_modulus, totals)
      type(shape_cache_t), intent(in) :: cache
      type(particles_t), intent(inout) :: particles
      type(grid_t), intent(in) :: grid
      real(dp), intent(in) :: dt, youngs_modulus
      type(pass_totals_t), intent(inout) :: totals
      integer :: p, k, i
      real(dp) :: rate
      totals%strain_energy = 0.0_dp
      totals%min_volume_ratio = huge(1.0_dp)
      do p = 1, particles%count
         rate = 0.0_dp
         do k = 1, cache%support
            i = cache%first(p) + k - 1
            if (i < 0) cycle
            rate = rate + cache%gradient(k, p)*grid%velocity(i)
         end do
         call elastic_update(youngs_modulus, dt*rate, particles%stress(p), particles%volume_ratio(p))
         totals%strain_energy = totals%strain_energy + strain_energy_density(youngs_modulus, particles%stress(p), &
                                                       particles%volume_ratio(p)*particles%volume0_of(p))
         totals%min_volume_ratio = min(totals%min_volume_ratio, particles%volume_ratio(p))
      end do
   end subroutine update_stress

   !> Kinetic and strain energy and the smallest J of the particles as they are (the initial state).
   subroutine particle_energies(particles, youngs_modulus, totals)
      type(particles_t), intent(in) :: particles
      real(dp), intent(in) :: youngs_modulus
      type(pass_totals_t), intent(out) :: totals
      totals%kinetic_energy = sum(0.5_dp*particles%mass_of*particles%v**2)
      totals%strain_energy = sum(strain_energy_density(youngs_modulus, particles%stress, &
                                                       particles%volume_ratio*particles%volume0_of))
      totals%min_volume_ratio = minval(particles%volume_ratio)
   end subroutine particle_energies
end module mpm_operations
