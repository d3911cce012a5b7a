!> The generic operations an MPM step is made of, for any shape function (through shape_cache_t),
!> per-particle masses and volumes, the scene's boundary conditions and forces:
!>   P2G:   m_I = sum_p N_Ip m_p,  p_I = sum_p N_Ip m_p v_p,  f_I = -sum_p dN_Ip sigma_p V_p
!>   solve: p_I += dt f_I,  a_I = f_I/m_I,  v_I = p_I/m_I  (empty nodes: 0; fixed nodes held)
!>   G2P:   x_p += dt sum_I N_Ip v_I and the velocity by the cache's transfer:
!>          FLIP  v_p += dt sum_I N_Ip a_I
!>          PIC   v_p  = sum_I N_Ip v_I
!>          blend v_p  = f (v_p + dt sum_I N_Ip a_I) + (1 - f) sum_I N_Ip v_I,  f = flip_fraction
!>          APIC  v_p  = sum_I N_Ip v_I and the velocity gradient C_p (Jiang, Schroeder, Selle, Teran and
!>                Stomakhin 2015, "The affine particle-in-cell method", ACM TOG 34(4), sec. 5.3):
!>                C_p = sum_I v_I dN_Ip (hat, GIMP: exact for their piecewise-linear weights) or
!>                C_p = B_p D_p^-1, B_p = sum_I N_Ip v_I (x_I - x_p), D_p = dx^2/4 (quadratic),
!>                dx^2/3 (cubic B-splines); P2G then adds sum_p N_Ip m_p C_p (x_I - x_p) to p_I.
!>   stress: d eps_p = dt sum_I dN_Ip v_I, then the material update (mpm_material_elastic)
!> Each is one loop over the particles (or nodes), serial: sweeps run cases on threads, and a run's
!> results are the same on any number of threads. The schemes (mpm_schemes) compose them.
!> Each public operation hands the arrays to a kernel with explicit contiguous dummies: gfortran then
!> keeps addresses in registers (through the derived types' descriptors the loops ran about 2x slower).
module mpm_operations
   use mpm_kinds, only: dp
   use mpm_grid, only: grid_t, solve_range, zero_fixed
   use mpm_particles, only: particles_t
   use mpm_shape, only: shape_cache_t, evaluate_shapes, shape_ugimp, shape_cpgimp, shape_bspline2, shape_bspline3, &
                        transfer_pic, transfer_blend, transfer_apic
   use mpm_diagnostics, only: pass_totals_t
   use mpm_material_elastic, only: elastic_update_all, elastic_update_each, strain_energy_density
   implicit none
   private
   public :: locate_particles, p2g_mass_momentum, p2g_internal_force, nodal_velocities, solve_grid, g2p, &
             update_stress, particle_energies, mirror_fold

contains

   !> Shape functions at the start-of-step positions; totals%outside = first particle outside the domain.
   subroutine locate_particles(cache, grid, particles, totals)
      type(shape_cache_t), intent(inout) :: cache
      type(grid_t), intent(in) :: grid
      type(particles_t), intent(in) :: particles
      type(pass_totals_t), intent(inout) :: totals
      integer :: outside
      select case (cache%kind)
      case (shape_ugimp)  ! the box of the particle's initial length, l_p0 = V0_p / 2 (per unit area)
         call scratch(cache, particles%count)
         cache%work(:, 1) = 0.5_dp*particles%volume0_of
         call evaluate_shapes(cache, grid, particles%x, outside, cache%work(:, 1))
      case (shape_cpgimp) ! stretched with the particle, l_p = l_p0 J_p
         call scratch(cache, particles%count)
         cache%work(:, 1) = 0.5_dp*particles%volume0_of*particles%volume_ratio
         call evaluate_shapes(cache, grid, particles%x, outside, cache%work(:, 1))
      case default
         call evaluate_shapes(cache, grid, particles%x, outside)
      end select
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
      if (cache%transfer == transfer_apic) &
         call scatter_affine(cache%support, cache%first, cache%weight, particles%mass_of, particles%velocity_gradient, &
                             cache%position, grid%origin, grid%dx, grid%momentum)
      call mirror_fold(grid, .true., with_force)
   end subroutine p2g_mass_momentum

   !> APIC's affine part of the momentum: p_I += sum_p N_Ip m_p C_p (x_I - x_p), x_p at the start of the
   !> step (it sums to zero over I, since sum_I N_Ip x_I = x_p: total momentum is unchanged).
   subroutine scatter_affine(support, first, weight, mass_of, velocity_gradient, position, origin, dx, momentum)
      integer, intent(in) :: support
      integer, intent(in), contiguous :: first(:)
      real(dp), intent(in), contiguous :: weight(:, :), mass_of(:), velocity_gradient(:), position(:)
      real(dp), intent(in) :: origin, dx
      real(dp), intent(inout), contiguous :: momentum(0:)
      integer :: p, k, i
      do p = 1, size(first)
         do k = 1, support
            i = first(p) + k - 1
            momentum(i) = momentum(i) + weight(p, k)*mass_of(p)*velocity_gradient(p)*(origin + i*dx - position(p))
         end do
      end do
   end subroutine scatter_affine

   !> At a fixed end with ghost cells (grid%mirror), the mirror image of the body beyond it: node
   !> c - j (c = grid%ghost, the fixed node at x = 0) is node c + j reflected. The body's image has the
   !> velocity -v(-x) and the stress sigma(-x) of an odd displacement field, so the image of a
   !> particle adds to node c + j what the particle adds to node c - j, with the sign of momentum and
   !> force reversed; the ghost node then holds the reflection of its partner (m, -p, -f), and the
   !> grid solve gives it -v, -a. This is exact where the solution is odd about the fixed end, as the
   !> elastic bar's (u = 0 there, and u_xx = u_tt/c^2 = 0 without a body force), so the wide shapes
   !> keep their interior accuracy at the fixed end; a body force there leaves a jump in u_xx.
   subroutine mirror_fold(grid, with_kinematics, with_force)
      type(grid_t), intent(inout) :: grid
      logical, intent(in) :: with_kinematics, with_force
      integer :: j, c
      call mirror_fold_right(grid, with_kinematics, with_force)
      if (.not. grid%mirror) return
      c = grid%ghost
      do j = 1, c
         if (with_kinematics) then
            grid%mass(c + j) = grid%mass(c + j) + grid%mass(c - j)
            grid%momentum(c + j) = grid%momentum(c + j) - grid%momentum(c - j)
            grid%mass(c - j) = grid%mass(c + j)
            grid%momentum(c - j) = -grid%momentum(c + j)
         end if
         if (with_force) then
            grid%force(c + j) = grid%force(c + j) - grid%force(c - j)
            grid%force(c - j) = -grid%force(c + j)
         end if
      end do
   end subroutine mirror_fold

   !> The mirror at a fixed right end x = L (grid%mirror_right = r, the manufactured scene's): margin
   !> node r + j is node r - j reflected, as mirror_fold does at x = 0 (the solution is odd about a
   !> fixed end there too). Without it the margin nodes beyond a fixed end moved freely, and the wide
   !> shapes' particles next to it followed them (first order, and through the wall at large strain).
   subroutine mirror_fold_right(grid, with_kinematics, with_force)
      type(grid_t), intent(inout) :: grid
      logical, intent(in) :: with_kinematics, with_force
      integer :: j, r
      r = grid%mirror_right
      if (r < 0) return
      do j = 1, grid%ghost
         if (with_kinematics) then
            grid%mass(r - j) = grid%mass(r - j) + grid%mass(r + j)
            grid%momentum(r - j) = grid%momentum(r - j) - grid%momentum(r + j)
            grid%mass(r + j) = grid%mass(r - j)
            grid%momentum(r + j) = -grid%momentum(r - j)
         end if
         if (with_force) then
            grid%force(r - j) = grid%force(r - j) - grid%force(r + j)
            grid%force(r + j) = -grid%force(r - j)
         end if
      end do
   end subroutine mirror_fold_right

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
      call mirror_fold(grid, .false., .true.)
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
      call zero_fixed(grid%fixed, grid%momentum)
      call zero_fixed(grid%fixed, grid%velocity)
   end subroutine nodal_velocities

   !> Explicit momentum update with the assembled force: p_I += dt f_I, a_I = f_I/m_I, v_I = p_I/m_I
   !> (empty nodes 0), fixed nodes held; grid%min_node_mass = the lightest node with mass.
   subroutine solve_grid(grid, dt)
      type(grid_t), intent(inout) :: grid
      real(dp), intent(in) :: dt
      call zero_fixed(grid%fixed, grid%force)
      call zero_fixed(grid%fixed, grid%momentum)
      grid%min_node_mass = huge(1.0_dp)
      call solve_range(0, grid%elements, dt, grid%empty_mass, grid%mass, grid%force, grid%momentum, grid%acceleration, &
                       grid%velocity, grid%min_node_mass)
      call zero_fixed(grid%fixed, grid%acceleration)
      call zero_fixed(grid%fixed, grid%velocity)
   end subroutine solve_grid

   !> Velocity (by the cache's transfer) and position update with the start-of-step shape functions;
   !> totals: sum m (x - X), kinetic energy, the largest move (cells) and its particle, the first
   !> particle outside the domain.
   subroutine g2p(cache, particles, grid, dt, totals)
      type(shape_cache_t), intent(inout) :: cache
      type(particles_t), intent(inout) :: particles
      type(grid_t), intent(in) :: grid
      real(dp), intent(in) :: dt
      type(pass_totals_t), intent(inout) :: totals
      call scratch(cache, particles%count)
      call gather_move(cache%support, cache%first, cache%weight, grid%acceleration, grid%velocity, dt, grid%inv_dx, &
                       grid%origin, grid%origin + grid%length, particles%mass_of, particles%x0, particles%x, &
                       particles%v, cache%work, totals, cache%transfer, cache%flip_fraction)
      if (cache%transfer == transfer_apic) then
         select case (cache%kind)
         case (shape_bspline2)
            call gather_affine(cache%support, cache%first, cache%weight, grid%velocity, cache%position, grid%origin, &
                               grid%dx, 4.0_dp*grid%inv_dx**2, particles%velocity_gradient)
         case (shape_bspline3)
            call gather_affine(cache%support, cache%first, cache%weight, grid%velocity, cache%position, grid%origin, &
                               grid%dx, 3.0_dp*grid%inv_dx**2, particles%velocity_gradient)
         case default
            ! C_p = sum_I v_I dN_Ip: the strain-rate gather (where B_p D_p^-1 reduces to it, piecewise-linear weights)
            call gather_strain(cache%support, cache%first, cache%gradient, grid%velocity, 1.0_dp, &
                               particles%velocity_gradient)
         end select
      end if
   end subroutine g2p

   !> C_p = B_p / D_p, B_p = sum_I N_Ip v_I (x_I - x_p) (APIC, Jiang et al. 2015, eq. 10 with D_p constant).
   subroutine gather_affine(support, first, weight, velocity, position, origin, dx, inverse_d, velocity_gradient)
      integer, intent(in) :: support
      integer, intent(in), contiguous :: first(:)
      real(dp), intent(in), contiguous :: weight(:, :), velocity(0:), position(:)
      real(dp), intent(in) :: origin, dx, inverse_d
      real(dp), intent(out), contiguous :: velocity_gradient(:)
      integer :: p, k, i
      velocity_gradient = 0.0_dp
      do k = 1, support
         do p = 1, size(first)
            i = first(p) + k - 1
            velocity_gradient(p) = velocity_gradient(p) + weight(p, k)*velocity(i)*(origin + i*dx - position(p))
         end do
      end do
      velocity_gradient = inverse_d*velocity_gradient
   end subroutine gather_affine

   subroutine gather_move(support, first, weight, acceleration, velocity, dt, inv_dx, lo, hi, mass_of, x0, x, v, &
                          gathered, totals, transfer, flip_fraction)
      integer, intent(in) :: support, transfer
      real(dp), intent(in) :: flip_fraction
      integer, intent(in), contiguous :: first(:)
      real(dp), intent(in), contiguous :: weight(:, :), acceleration(0:), velocity(0:), mass_of(:), x0(:)
      real(dp), intent(in) :: dt, inv_dx, lo, hi
      real(dp), intent(inout), contiguous :: x(:), v(:)
      real(dp), intent(inout), contiguous :: gathered(:, :)  !< scratch: sum N a, sum N v per particle
      type(pass_totals_t), intent(inout) :: totals
      integer :: p, k, outside, furthest
      real(dp) :: move, largest, displacement, kinetic
      ! the gathers, node by node of the support (each loop vectorises; the first node assigns)
      do p = 1, size(first)
         gathered(p, 1) = weight(p, 1)*acceleration(first(p))
         gathered(p, 2) = weight(p, 1)*velocity(first(p))
      end do
      do k = 2, support
         do p = 1, size(first)
            gathered(p, 1) = gathered(p, 1) + weight(p, k)*acceleration(first(p) + k - 1)
            gathered(p, 2) = gathered(p, 2) + weight(p, k)*velocity(first(p) + k - 1)
         end do
      end do
      select case (transfer)
      case (transfer_pic, transfer_apic)
         v = gathered(:, 2)
      case (transfer_blend)
         v = flip_fraction*(v + dt*gathered(:, 1)) + (1.0_dp - flip_fraction)*gathered(:, 2)
      case default ! transfer_flip
         v = v + dt*gathered(:, 1)
      end select
      x = x + dt*gathered(:, 2)
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
      do p = 1, size(first)
         dstrain(p) = gradient(p, 1)*velocity(first(p))
      end do
      do k = 2, support
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
