!> Particle <-> grid transfers with linear shape functions, written as fused passes over the
!> particles: each pass reads and writes every particle once, so a time step costs one or two
!> sweeps through particle memory instead of four or five. Each scheme composes these passes
!> (see mpm_scheme_*). Every pass accumulates the per-step totals the diagnostics and guards need.
!>
!> Notation: a particle in element e with local coordinate xi has N_left = 1 - xi on node e-1 and
!> N_right = xi on node e; dN = -/+ 1/dx. Grid nodal arrays are indexed 0..elements.
module mpm_transfer
   use mpm_kinds, only: dp
   use mpm_grid, only: grid_t
   use mpm_particles, only: particles_t
   use mpm_shape, only: locate, shape_left, shape_right
   use mpm_material, only: elastic_update, strain_energy_density
   implicit none
   private
   public :: pass_totals_t, clear_element_shares, merge_totals
   public :: p2g, g2p_then_p2g, stress_then_force, g2p_stress_then_p2g, g2p_with_remap, stress_then_p2g

   !> Sums and extremes gathered during a pass over the particles.
   type :: pass_totals_t
      !> sum_p (x_p - X_p) after the pass: with equal particle masses, count * u_cm.
      real(dp) :: displacement = 0.0_dp
      !> sum_p m_p v_p^2 / 2 with the velocities after the pass (when the pass updates them).
      real(dp) :: kinetic_energy = 0.0_dp
      !> sum_p sigma_p^2 V_p / (2E) with the stresses after the pass (when the pass updates them).
      real(dp) :: strain_energy = 0.0_dp
      !> smallest volume ratio J seen (after the update, when the pass updates it).
      real(dp) :: min_volume_ratio = huge(1.0_dp)
      !> largest |x_new - x_old| / dx of the pass (when the pass moves particles).
      real(dp) :: max_cell_move = 0.0_dp
      !> the particle that moved furthest in the pass.
      integer :: furthest = 0
      !> first particle found outside the grid, 0 if none.
      integer :: outside = 0
   end type pass_totals_t

contains

   !> Zero the per-element accumulators before a scatter.
   subroutine clear_element_shares(grid, with_momentum, with_stress)
      type(grid_t), intent(inout) :: grid
      logical, intent(in) :: with_momentum, with_stress
      if (with_momentum) then
         grid%element_mass_left = 0.0_dp
         grid%element_mass_right = 0.0_dp
         grid%element_momentum_left = 0.0_dp
         grid%element_momentum_right = 0.0_dp
      end if
      if (with_stress) grid%element_stress_volume = 0.0_dp
   end subroutine clear_element_shares

   !> Plain particle-to-grid transfer at the current positions: element shares of mass,
   !> momentum and (when `with_stress`) stress*volume; records each particle's cell.
   subroutine p2g(particles, grid, with_stress, totals)
      type(particles_t), intent(inout) :: particles
      type(grid_t), intent(inout) :: grid
      logical, intent(in) :: with_stress
      type(pass_totals_t), intent(out) :: totals
      integer :: p, e
      real(dp) :: xi, m
      call clear_element_shares(grid, .true., with_stress)
      m = particles%mass
      do p = 1, particles%count
         call locate(particles%x(p), grid%inv_dx, grid%elements, e, xi)
         if (e < 1 .or. e > grid%elements) then
            if (totals%outside == 0) totals%outside = p
            cycle
         end if
         particles%cell(p) = e
         call scatter_mass_momentum(grid, e, xi, m, particles%v(p))
         if (with_stress) grid%element_stress_volume(e) = grid%element_stress_volume(e) + &
                                                          particles%stress(p)*particles%volume_ratio(p)*particles%volume0
         totals%kinetic_energy = totals%kinetic_energy + 0.5_dp*m*particles%v(p)**2
         totals%min_volume_ratio = min(totals%min_volume_ratio, particles%volume_ratio(p))
      end do
   end subroutine p2g

   !> USF, second half: grid-to-particle update with the solved grid (v_p += dt sum N a_I,
   !> x_p += dt sum N v_I), then mass and momentum of the moved particles to the grid for the next step.
   subroutine g2p_then_p2g(particles, grid, dt, totals)
      type(particles_t), intent(inout) :: particles
      type(grid_t), intent(inout) :: grid
      real(dp), intent(in) :: dt
      type(pass_totals_t), intent(out) :: totals
      integer :: p, e
      real(dp) :: xi, m, dxp
      call clear_element_shares(grid, .true., .false.)
      m = particles%mass
      do p = 1, particles%count
         call g2p_particle(particles, grid, p, dt, dxp)
         call account_move(totals, p, m, dxp, grid%inv_dx, particles%v(p), particles%x(p) - particles%x0(p))
         call locate(particles%x(p), grid%inv_dx, grid%elements, e, xi)
         if (e < 1 .or. e > grid%elements) then
            if (totals%outside == 0) totals%outside = p
            cycle
         end if
         particles%cell(p) = e
         call scatter_mass_momentum(grid, e, xi, m, particles%v(p))
      end do
   end subroutine g2p_then_p2g

   !> USF, first half: stress update from the nodal velocities of this step's mapping
   !> (d eps = dt sum dN v_I), then the element shares of stress*volume for the internal force.
   subroutine stress_then_force(particles, grid, dt, youngs_modulus, totals)
      type(particles_t), intent(inout) :: particles
      type(grid_t), intent(inout) :: grid
      real(dp), intent(in) :: dt, youngs_modulus
      type(pass_totals_t), intent(out) :: totals
      integer :: p, e
      call clear_element_shares(grid, .false., .true.)
      do p = 1, particles%count
         e = particles%cell(p)
         call stress_particle(particles, grid, p, e, dt, youngs_modulus, totals)
         grid%element_stress_volume(e) = grid%element_stress_volume(e) + &
                                         particles%stress(p)*particles%volume_ratio(p)*particles%volume0
      end do
   end subroutine stress_then_force

   !> USL in one pass: grid-to-particle update, stress update from the updated nodal velocities,
   !> then mass, momentum and stress*volume of the moved particles to the grid for the next step.
   subroutine g2p_stress_then_p2g(particles, grid, dt, youngs_modulus, totals)
      type(particles_t), intent(inout) :: particles
      type(grid_t), intent(inout) :: grid
      real(dp), intent(in) :: dt, youngs_modulus
      type(pass_totals_t), intent(out) :: totals
      integer :: p, e
      real(dp) :: xi, m, dxp
      call clear_element_shares(grid, .true., .true.)
      m = particles%mass
      do p = 1, particles%count
         e = particles%cell(p)
         call g2p_particle(particles, grid, p, dt, dxp)
         call account_move(totals, p, m, dxp, grid%inv_dx, particles%v(p), particles%x(p) - particles%x0(p))
         call stress_particle(particles, grid, p, e, dt, youngs_modulus, totals)
         call locate(particles%x(p), grid%inv_dx, grid%elements, e, xi)
         if (e < 1 .or. e > grid%elements) then
            if (totals%outside == 0) totals%outside = p
            cycle
         end if
         particles%cell(p) = e
         call scatter_mass_momentum(grid, e, xi, m, particles%v(p))
         grid%element_stress_volume(e) = grid%element_stress_volume(e) + &
                                         particles%stress(p)*particles%volume_ratio(p)*particles%volume0
      end do
   end subroutine g2p_stress_then_p2g

   !> MUSL, first pass: grid-to-particle update, and the updated particle momentum mapped back to
   !> the grid with the same (start-of-step) shape functions. Mass shares are unchanged.
   subroutine g2p_with_remap(particles, grid, dt, totals)
      type(particles_t), intent(inout) :: particles
      type(grid_t), intent(inout) :: grid
      real(dp), intent(in) :: dt
      type(pass_totals_t), intent(out) :: totals
      integer :: p, e
      real(dp) :: xi, m, dxp, mv
      grid%element_momentum_left = 0.0_dp
      grid%element_momentum_right = 0.0_dp
      m = particles%mass
      do p = 1, particles%count
         e = particles%cell(p)
         xi = particles%x(p)*grid%inv_dx - (e - 1)
         call g2p_particle(particles, grid, p, dt, dxp)
         call account_move(totals, p, m, dxp, grid%inv_dx, particles%v(p), particles%x(p) - particles%x0(p))
         mv = m*particles%v(p)
         grid%element_momentum_left(e) = grid%element_momentum_left(e) + shape_left(xi)*mv
         grid%element_momentum_right(e) = grid%element_momentum_right(e) + shape_right(xi)*mv
      end do
   end subroutine g2p_with_remap

   !> MUSL, second pass: stress update from the remapped nodal velocities (start-of-step cell),
   !> then mass, momentum and stress*volume at the new positions for the next step.
   subroutine stress_then_p2g(particles, grid, dt, youngs_modulus, totals)
      type(particles_t), intent(inout) :: particles
      type(grid_t), intent(inout) :: grid
      real(dp), intent(in) :: dt, youngs_modulus
      type(pass_totals_t), intent(out) :: totals
      integer :: p, e
      real(dp) :: xi, m
      call clear_element_shares(grid, .true., .true.)
      m = particles%mass
      do p = 1, particles%count
         call stress_particle(particles, grid, p, particles%cell(p), dt, youngs_modulus, totals)
         call locate(particles%x(p), grid%inv_dx, grid%elements, e, xi)
         if (e < 1 .or. e > grid%elements) then
            if (totals%outside == 0) totals%outside = p
            cycle
         end if
         particles%cell(p) = e
         call scatter_mass_momentum(grid, e, xi, m, particles%v(p))
         grid%element_stress_volume(e) = grid%element_stress_volume(e) + &
                                         particles%stress(p)*particles%volume_ratio(p)*particles%volume0
      end do
   end subroutine stress_then_p2g

   !> Combine the totals of the two passes of one step (each pass fills different sums).
   pure subroutine merge_totals(totals, other)
      type(pass_totals_t), intent(inout) :: totals
      type(pass_totals_t), intent(in) :: other
      totals%displacement = totals%displacement + other%displacement
      totals%kinetic_energy = totals%kinetic_energy + other%kinetic_energy
      totals%strain_energy = totals%strain_energy + other%strain_energy
      totals%min_volume_ratio = min(totals%min_volume_ratio, other%min_volume_ratio)
      if (other%max_cell_move > totals%max_cell_move) then
         totals%max_cell_move = other%max_cell_move
         totals%furthest = other%furthest
      end if
      if (totals%outside == 0) totals%outside = other%outside
   end subroutine merge_totals

   ! ---- per-particle building blocks (inlined by the compiler) ----

   !> v_p += dt sum N a_I; x_p += dt sum N v_I, with the shape functions of the particle's
   !> start-of-step cell. Returns the displacement increment.
   pure subroutine g2p_particle(particles, grid, p, dt, dxp)
      type(particles_t), intent(inout) :: particles
      type(grid_t), intent(in) :: grid
      integer, intent(in) :: p
      real(dp), intent(in) :: dt
      real(dp), intent(out) :: dxp
      integer :: e
      real(dp) :: xi, n0, n1
      e = particles%cell(p)
      xi = particles%x(p)*grid%inv_dx - (e - 1)
      n0 = shape_left(xi)
      n1 = shape_right(xi)
      particles%v(p) = particles%v(p) + dt*(n0*grid%acceleration(e - 1) + n1*grid%acceleration(e))
      dxp = dt*(n0*grid%velocity(e - 1) + n1*grid%velocity(e))
      particles%x(p) = particles%x(p) + dxp
   end subroutine g2p_particle

   !> d eps = dt sum dN v_I over cell e; elastic update; strain energy and J totals.
   pure subroutine stress_particle(particles, grid, p, e, dt, youngs_modulus, totals)
      type(particles_t), intent(inout) :: particles
      type(grid_t), intent(in) :: grid
      integer, intent(in) :: p, e
      real(dp), intent(in) :: dt, youngs_modulus
      type(pass_totals_t), intent(inout) :: totals
      real(dp) :: dstrain
      dstrain = dt*(grid%velocity(e) - grid%velocity(e - 1))*grid%inv_dx
      call elastic_update(youngs_modulus, dstrain, particles%stress(p), particles%volume_ratio(p))
      totals%strain_energy = totals%strain_energy + &
                             strain_energy_density(youngs_modulus, particles%stress(p), &
                                                   particles%volume_ratio(p)*particles%volume0)
      totals%min_volume_ratio = min(totals%min_volume_ratio, particles%volume_ratio(p))
   end subroutine stress_particle

   pure subroutine account_move(totals, p, m, dxp, inv_dx, v, displacement)
      type(pass_totals_t), intent(inout) :: totals
      integer, intent(in) :: p
      real(dp), intent(in) :: m, dxp, inv_dx, v, displacement
      real(dp) :: move
      totals%displacement = totals%displacement + displacement
      totals%kinetic_energy = totals%kinetic_energy + 0.5_dp*m*v*v
      move = abs(dxp)*inv_dx
      if (move > totals%max_cell_move) then
         totals%max_cell_move = move
         totals%furthest = p
      end if
   end subroutine account_move

   pure subroutine scatter_mass_momentum(grid, e, xi, m, v)
      type(grid_t), intent(inout) :: grid
      integer, intent(in) :: e
      real(dp), intent(in) :: xi, m, v
      real(dp) :: n0, n1
      n0 = shape_left(xi)
      n1 = shape_right(xi)
      grid%element_mass_left(e) = grid%element_mass_left(e) + n0*m
      grid%element_mass_right(e) = grid%element_mass_right(e) + n1*m
      grid%element_momentum_left(e) = grid%element_momentum_left(e) + n0*m*v
      grid%element_momentum_right(e) = grid%element_momentum_right(e) + n1*m*v
   end subroutine scatter_mass_momentum
end module mpm_transfer
