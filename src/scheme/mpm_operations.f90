!> The generic operations an MPM step is made of, for any shape function (through shape_cache_t),
!> per-particle masses and volumes, the scene's boundary conditions and forces:
!>   P2G:   m_I = sum_p N_Ip m_p,  p_I = sum_p N_Ip m_p v_p,  f_I = -sum_p dN_Ip sigma_p V_p
!>   solve: p_I += dt f_I,  a_I = f_I/m_I,  v_I = p_I/m_I  (empty nodes: 0; fixed nodes held)
!>   G2P:   v_p += dt sum_I N_Ip a_I (FLIP),  x_p += dt sum_I N_Ip v_I
!>   stress: d eps_p = dt sum_I dN_Ip v_I, then the material update (mpm_material_elastic)
!> Each is one loop over the particles (or nodes), serial: sweeps run cases on threads, and a run's
!> results are the same on any number of threads. The schemes (mpm_schemes) compose them.
!> Each public operation hands the arrays to a kernel with explicit contiguous dummies: gfortran then
!> keeps addresses in registers (through the derived types' descriptors the loops ran about 2x slower).
module mpm_operations
   use mpm_kinds, only: dp
   use mpm_grid, only: grid_t, solve_range
   use mpm_particles, only: particles_t
   use mpm_shape, only: shape_cache_t, evaluate_shapes
   use mpm_diagnostics, only: pass_totals_t
   use mpm_material_elastic, only: elastic_update_all, elastic_update_each, strain_energy_density
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

   !> m_I and p_I from the particles (grid fields cleared first); with `with_force` also the internal
   !> force f_I = -sum_p dN_Ip sigma_p V_p, V_p = J_p V0_p, in the same pass.
   subroutine p2g_mass_momentum(cache, particles, grid, with_force)
      type(shape_cache_t), intent(in) :: cache
      type(particles_t), intent(in) :: particles
      type(grid_t), intent(inout) :: grid
      logical, intent(in) :: with_force
      grid%mass = 0.0_dp
      grid%momentum = 0.0_dp
      if (with_force) then
         grid%force = 0.0_dp
         call scatter_all(cache%support, cache%first, cache%weight, cache%gradient, particles%mass_of, particles%v, &
                          particles%stress, particles%volume_ratio, particles%volume0_of, grid%mass, grid%momentum, &
                          grid%force)
      else
         call scatter_kinematic(cache%support, cache%first, cache%weight, particles%mass_of, particles%v, grid%mass, &
                                grid%momentum)
      end if
   end subroutine p2g_mass_momentum

   subroutine scatter_kinematic(support, first, weight, mass_of, v, mass, momentum)
      integer, intent(in) :: support
      integer, intent(in), contiguous :: first(:)
      real(dp), intent(in), contiguous :: weight(:, :), mass_of(:), v(:)
      real(dp), intent(inout), contiguous :: mass(0:), momentum(0:)
      integer :: p, k, i
      real(dp) :: wm
      do p = 1, size(first)
         do k = 1, support
            i = first(p) + k - 1
            wm = weight(p, k)*mass_of(p)
            mass(i) = mass(i) + wm
            momentum(i) = momentum(i) + wm*v(p)
         end do
      end do
   end subroutine scatter_kinematic

   subroutine scatter_all(support, first, weight, gradient, mass_of, v, stress, volume_ratio, volume0_of, mass, &
                          momentum, force)
      integer, intent(in) :: support
      integer, intent(in), contiguous :: first(:)
      real(dp), intent(in), contiguous :: weight(:, :), gradient(:, :), mass_of(:), v(:), stress(:), volume_ratio(:), &
                                          volume0_of(:)
      real(dp), intent(inout), contiguous :: mass(0:), momentum(0:), force(0:)
      integer :: p, k, i
      real(dp) :: wm, sv
      do p = 1, size(first)
         sv = stress(p)*volume_ratio(p)*volume0_of(p)
         do k = 1, support
            i = first(p) + k - 1
            wm = weight(p, k)*mass_of(p)
            mass(i) = mass(i) + wm
            momentum(i) = momentum(i) + wm*v(p)
            force(i) = force(i) - gradient(p, k)*sv
         end do
      end do
   end subroutine scatter_all

   !> f_I = -sum_p dN_Ip sigma_p V_p, V_p = J_p V0_p (grid force cleared first).
   subroutine p2g_internal_force(cache, particles, grid)
      type(shape_cache_t), intent(in) :: cache
      type(particles_t), intent(in) :: particles
      type(grid_t), intent(inout) :: grid
      grid%force = 0.0_dp
      call scatter_force(cache%support, cache%first, cache%gradient, particles%stress, particles%volume_ratio, &
                         particles%volume0_of, grid%force)
   end subroutine p2g_internal_force

   subroutine scatter_force(support, first, gradient, stress, volume_ratio, volume0_of, force)
      integer, intent(in) :: support
      integer, intent(in), contiguous :: first(:)
      real(dp), intent(in), contiguous :: gradient(:, :), stress(:), volume_ratio(:), volume0_of(:)
      real(dp), intent(inout), contiguous :: force(0:)
      integer :: p, k, i
      real(dp) :: sv
      do p = 1, size(first)
         sv = stress(p)*volume_ratio(p)*volume0_of(p)
         do k = 1, support
            i = first(p) + k - 1
            force(i) = force(i) - gradient(p, k)*sv
         end do
      end do
   end subroutine scatter_force

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
      grid%force(grid%fixed) = 0.0_dp
      grid%momentum(grid%fixed) = 0.0_dp
      grid%min_node_mass = huge(1.0_dp)
      call solve_range(0, grid%elements, dt, grid%empty_mass, grid%mass, grid%force, grid%momentum, grid%acceleration, &
                       grid%velocity, grid%min_node_mass)
      grid%acceleration(grid%fixed) = 0.0_dp
      grid%velocity(grid%fixed) = 0.0_dp
   end subroutine solve_grid

   !> FLIP update of velocity and position with the start-of-step shape functions; totals: sum m (x - X),
   !> kinetic energy, the largest move (cells) and its particle, the first particle outside the domain.
   subroutine g2p(cache, particles, grid, dt, totals)
      type(shape_cache_t), intent(inout) :: cache
      type(particles_t), intent(inout) :: particles
      type(grid_t), intent(in) :: grid
      real(dp), intent(in) :: dt
      type(pass_totals_t), intent(inout) :: totals
      call scratch(cache, particles%count)
      call gather_move(cache%support, cache%first, cache%weight, grid%acceleration, grid%velocity, dt, grid%inv_dx, &
                       grid%origin, grid%origin + grid%length, particles%mass_of, particles%x0, particles%x, &
                       particles%v, cache%work, totals)
   end subroutine g2p

   subroutine gather_move(support, first, weight, acceleration, velocity, dt, inv_dx, lo, hi, mass_of, x0, x, v, &
                          gathered, totals)
      integer, intent(in) :: support
      integer, intent(in), contiguous :: first(:)
      real(dp), intent(in), contiguous :: weight(:, :), acceleration(0:), velocity(0:), mass_of(:), x0(:)
      real(dp), intent(in) :: dt, inv_dx, lo, hi
      real(dp), intent(inout), contiguous :: x(:), v(:)
      real(dp), intent(inout), contiguous :: gathered(:, :)  !< scratch: sum N a, sum N v per particle
      type(pass_totals_t), intent(inout) :: totals
      integer :: p, k, outside, furthest
      real(dp) :: move, largest, displacement, kinetic
      ! the gathers, node by node of the support (each loop vectorises)
      gathered(:, 1:2) = 0.0_dp
      do k = 1, support
         do p = 1, size(first)
            gathered(p, 1) = gathered(p, 1) + weight(p, k)*acceleration(first(p) + k - 1)
            gathered(p, 2) = gathered(p, 2) + weight(p, k)*velocity(first(p) + k - 1)
         end do
      end do
      do p = 1, size(first)
         v(p) = v(p) + dt*gathered(p, 1)
         x(p) = x(p) + dt*gathered(p, 2)
      end do
      outside = 0
      furthest = 0
      largest = 0.0_dp
      displacement = 0.0_dp
      kinetic = 0.0_dp
      do p = 1, size(first)
         move = abs(dt*gathered(p, 2))*inv_dx
         if (move > largest) then
            largest = move
            furthest = p
         end if
         if (.not. (x(p) >= lo .and. x(p) <= hi) .and. outside == 0) outside = p
         displacement = displacement + mass_of(p)*(x(p) - x0(p))
         kinetic = kinetic + 0.5_dp*mass_of(p)*v(p)*v(p)
      end do
      totals%displacement = displacement
      totals%kinetic_energy = kinetic
      totals%max_cell_move = largest
      totals%furthest = furthest
      if (totals%outside == 0) totals%outside = outside
   end subroutine gather_move

   !> Strain increment d eps = dt sum_I dN_Ip v_I and the material update (the run's Young's modulus, or
   !> each particle's where the scene gave one); totals: strain energy, min J.
   subroutine update_stress(cache, particles, grid, dt, youngs_modulus, totals)
      type(shape_cache_t), intent(inout) :: cache
      type(particles_t), intent(inout) :: particles
      type(grid_t), intent(in) :: grid
      real(dp), intent(in) :: dt, youngs_modulus
      type(pass_totals_t), intent(inout) :: totals
      call scratch(cache, particles%count)
      call gather_strain(cache%support, cache%first, cache%gradient, grid%velocity, dt, cache%work(:, 1))
      if (allocated(particles%youngs_modulus_of)) then ! several materials (one test per step, none per particle)
         call elastic_update_each(particles%youngs_modulus_of, cache%work(:, 1), particles%volume0_of, &
                                  particles%stress, particles%volume_ratio, totals%strain_energy, &
                                  totals%min_volume_ratio)
      else
         call elastic_update_all(youngs_modulus, cache%work(:, 1), particles%volume0_of, particles%stress, &
                                 particles%volume_ratio, totals%strain_energy, totals%min_volume_ratio)
      end if
   end subroutine update_stress

   subroutine gather_strain(support, first, gradient, velocity, dt, dstrain)
      integer, intent(in) :: support
      integer, intent(in), contiguous :: first(:)
      real(dp), intent(in), contiguous :: gradient(:, :), velocity(0:)
      real(dp), intent(in) :: dt
      real(dp), intent(out), contiguous :: dstrain(:)
      integer :: p, k
      dstrain = 0.0_dp
      do k = 1, support
         do p = 1, size(first)
            dstrain(p) = dstrain(p) + gradient(p, k)*velocity(first(p) + k - 1)
         end do
      end do
      dstrain = dt*dstrain
   end subroutine gather_strain

   !> The operations' scratch arrays, allocated on first use.
   subroutine scratch(cache, count)
      type(shape_cache_t), intent(inout) :: cache
      integer, intent(in) :: count
      if (.not. allocated(cache%work)) allocate (cache%work(count, 2))
   end subroutine scratch

   !> Kinetic and strain energy and the smallest J of the particles as they are (the initial state).
   subroutine particle_energies(particles, youngs_modulus, totals)
      type(particles_t), intent(in) :: particles
      real(dp), intent(in) :: youngs_modulus
      type(pass_totals_t), intent(out) :: totals
      totals%kinetic_energy = sum(0.5_dp*particles%mass_of*particles%v**2)
      if (allocated(particles%youngs_modulus_of)) then
         totals%strain_energy = sum(strain_energy_density(particles%youngs_modulus_of, particles%stress, &
                                                          particles%volume_ratio*particles%volume0_of))
      else
         totals%strain_energy = sum(strain_energy_density(youngs_modulus, particles%stress, &
                                                          particles%volume_ratio*particles%volume0_of))
      end if
      totals%min_volume_ratio = minval(particles%volume_ratio)
   end subroutine particle_energies
end module mpm_operations
