!> The background mesh: a uniform 1-D grid of 2-node linear elements over the grid domain
!> [origin, origin + elements dx], lumped mass. The domain is the scene's: it may extend beyond the
!> body by empty cells (a free end moves out), and the nodes held at rest (`fixed`) are the scene's
!> boundary conditions. Empty nodes (no mass) get zero velocity and acceleration.
!>
!> Particle-to-grid transfers accumulate per element first (`element_*` arrays: the share of
!> the element's left and right node), then `assemble_nodes` adds the two neighbouring elements'
!> shares in a fixed order. This keeps sums independent of how particles are split between threads.
module mpm_grid
   use omp_lib, only: omp_in_parallel
   use mpm_kinds, only: dp
   use mpm_errors, only: error_t, set_error
   use mpm_strings, only: str
   use mpm_state, only: state_t
   implicit none
   private
   public :: grid_t, grid_init, assemble_nodes, assemble_and_solve, nodal_velocity, solve_momentum, mass_tolerance
   public :: nodal_kinematics
   public :: parallel_nodes, node_chunk, threaded_nodes, solve_range, zero_fixed
   public :: grid_loads_t, element_forces, sync_grid

   !> Nodes lighter than this fraction of one particle's mass are treated as empty.
   real(dp), parameter :: mass_tolerance = 1.0e-12_dp

   !> External loads the scene registers as grid operations (applied where the nodal force is
   !> assembled from the element shares, after the node's mass and momentum: the fused kernels'
   !> path; the generic path applies the same loads in the scene's add_forces):
   !> - a uniform body acceleration (m/s^2): f_I += m_I a (a column's weight);
   !> - a driven node (its index, -1: none): its force set to (m_I v - p_I)/dt, so that the momentum
   !>   update gives it the velocity v (a composite bar's driven end).
   type :: grid_loads_t
      real(dp) :: acceleration = 0.0_dp
      integer :: driven_node = -1
      real(dp) :: drive_velocity = 0.0_dp, drive_dt = 1.0_dp
   end type grid_loads_t

   !> Grids of at least this many elements update their nodes on threads (see threaded_nodes), in
   !> chunks of `node_chunk` nodes (the arrays of a chunk stay in a core's L2 cache).
   integer, parameter :: parallel_nodes = 50000, node_chunk = 8192
   !> Grids of at most this many elements (without external loads) assemble and solve their nodes in one
   !> loop (solve_small): the general path's calls and its vector loops' set-up and remainders were about
   !> a third of a small grid's work; a larger one keeps the separate vector loops of the assembly (in one
   !> loop, each node took 1.5 more instructions: 20.5 against 19 at 5000 elements).
   integer, parameter :: small_nodes = 128

   !> Grid state. Nodes are numbered 0..elements; element e spans nodes e-1 and e.
   type :: grid_t
      !> Cells of the grid domain (the body's elements plus the empty margin cells).
      integer :: elements = 0
      !> Position of node 0 (m) and length of the domain, elements * dx (m).
      real(dp) :: origin = 0.0_dp
      real(dp) :: length = 0.0_dp
      real(dp) :: dx = 0.0_dp
      real(dp) :: inv_dx = 0.0_dp
      !> Nodal mass below which a node is skipped (mass_tolerance times a particle's mass).
      real(dp) :: empty_mass = 0.0_dp
      !> Per-element shares: mass and momentum at the left (N0) and right (N1) node,
      !> and the element's sum of stress * volume (its internal force is -/+ that / dx).
      real(dp), allocatable :: element_mass_left(:), element_mass_right(:)
      real(dp), allocatable :: element_momentum_left(:), element_momentum_right(:)
      real(dp), allocatable :: element_stress_volume(:)
      !> Strain increment of each element in a step, dt (v_e - v_{e-1}) / dx (`strain_increments`):
      !> the passes that only update the stress read one value per particle instead of two.
      real(dp), allocatable :: element_strain(:)
      !> Per-element shares of external forces that differ between particles (sum N f_p at the left and
      !> right node): allocated only for a run that has them (element_forces), else unallocated.
      real(dp), allocatable :: element_force_left(:), element_force_right(:)
      !> The scene's loads on the nodes (see grid_loads_t; default none).
      type(grid_loads_t) :: loads
      !> Nodal fields, index 0..elements.
      real(dp), allocatable :: mass(:), momentum(:), force(:), velocity(:), acceleration(:)
      !> Smallest nodal mass met by `solve_momentum` in this step (diagnostic of marginal runs).
      real(dp) :: min_node_mass = huge(1.0_dp)
      !> Nodes held at rest (zero momentum, force, acceleration and velocity): the scene's fixed ends.
      integer, allocatable :: fixed(:)
      !> Ghost cells left of x = 0 (shapes wider than the hat; origin = -ghost dx) and, when node
      !> `ghost` (x = 0) is fixed, the mirror: ghost node ghost - j is node ghost + j reflected (mirror_fold).
      integer :: ghost = 0
      logical :: mirror = .false.
      !> The same at the body's right end x = L when it is fixed (node mirror_right; -1: none): margin
      !> node mirror_right + j is node mirror_right - j reflected.
      integer :: mirror_right = -1
   end type grid_t

contains

   !> Allocate a grid whose cells have the size of `body_elements` elements over `body_length` (dx =
   !> body_length / body_elements, so dx and 1/dx are those of a grid that ends at the body), starting
   !> at x = 0 and extending `margin` more empty cells to the right (default none). `fixed` lists the
   !> nodes held at rest (default none). `particle_mass` sets the empty-node test. The per-element
   !> shares of the fused kernels are allocated only when `element_shares` (default true).
   !> `ghost` (default 0) more cells left of x = 0 (the origin moves to -ghost dx; `fixed` keeps
   !> numbering the body's nodes from x = 0 and is shifted): when the node at x = 0 is fixed they are
   !> mirror ghosts, else empty cells.
   subroutine grid_init(grid, body_elements, body_length, particle_mass, error, margin, fixed, element_shares, ghost)
      type(grid_t), intent(out) :: grid
      integer, intent(in) :: body_elements
      real(dp), intent(in) :: body_length, particle_mass
      type(error_t), allocatable, intent(out) :: error
      integer, intent(in), optional :: margin
      integer, intent(in), optional :: fixed(:)
      logical, intent(in), optional :: element_shares
      integer, intent(in), optional :: ghost
      integer :: stat, elements, share_elements
      if (present(ghost)) grid%ghost = ghost
      elements = body_elements + grid%ghost
      if (present(margin)) elements = elements + margin
      grid%elements = elements
      grid%dx = body_length/body_elements
      grid%inv_dx = body_elements/body_length
      grid%length = elements*grid%dx
      grid%origin = -grid%ghost*grid%dx
      grid%empty_mass = mass_tolerance*particle_mass
      if (present(fixed)) then
         grid%fixed = fixed + grid%ghost
      else
         allocate (grid%fixed(0))
      end if
      grid%mirror = grid%ghost > 0 .and. any(grid%fixed == grid%ghost)
      if (grid%ghost > 0 .and. any(grid%fixed == body_elements + grid%ghost) .and. &
          elements - (body_elements + grid%ghost) >= grid%ghost) grid%mirror_right = body_elements + grid%ghost
      share_elements = elements
      if (present(element_shares)) then
         if (.not. element_shares) share_elements = 0
      end if
      allocate (grid%element_mass_left(share_elements), grid%element_mass_right(share_elements), &
                grid%element_momentum_left(share_elements), grid%element_momentum_right(share_elements), &
                grid%element_stress_volume(share_elements), grid%element_strain(share_elements), &
                grid%mass(0:elements), grid%momentum(0:elements), grid%force(0:elements), &
                grid%velocity(0:elements), grid%acceleration(0:elements), stat=stat)
      if (stat /= 0) then
         call set_error(error, "cannot allocate a grid of "//str(elements)//" elements (out of memory)")
         return
      end if
      grid%element_mass_left = 0.0_dp
      grid%element_mass_right = 0.0_dp
      grid%element_momentum_left = 0.0_dp
      grid%element_momentum_right = 0.0_dp
      grid%element_stress_volume = 0.0_dp
      grid%element_strain = 0.0_dp
      grid%mass = 0.0_dp
      grid%momentum = 0.0_dp
      grid%force = 0.0_dp
      grid%velocity = 0.0_dp
      grid%acceleration = 0.0_dp
   end subroutine grid_init

   !> Grids of at least this many elements update their nodes in chunks of `node_chunk` nodes on
   !> OpenMP threads (unless already inside a parallel region: a sweep). Every node is computed by the
   !> same expression whatever the chunk or thread, so results do not depend on the thread count.
   logical function threaded_nodes(grid)
      type(grid_t), intent(in) :: grid
      threaded_nodes = .false.  ! (nested: omp_in_parallel, a library call, only for a large grid)
      if (grid%elements >= parallel_nodes) threaded_nodes = .not. omp_in_parallel()
   end function threaded_nodes

   !> Nodal mass, momentum and (when `with_force`) internal force from the element shares.
   !> The fixed node 0 gets zero momentum and force.
   subroutine assemble_nodes(grid, with_force)
      type(grid_t), intent(inout) :: grid
      logical, intent(in) :: with_force
      integer :: k
      call assemble_ends(grid, with_force)
      if (threaded_nodes(grid)) then
         !$omp parallel do default(shared) private(k) schedule(static)
         do k = 0, grid%elements/node_chunk
            call assemble_interior(grid, with_force, k*node_chunk, min(grid%elements, (k + 1)*node_chunk - 1))
         end do
         !$omp end parallel do
      else
         call assemble_interior(grid, with_force, 0, grid%elements)
      end if
      call hold_fixed_nodes(grid, with_force)
   end subroutine assemble_nodes

   !> Zero momentum (and force, when assembled) of the fixed nodes after an assembly.
   subroutine hold_fixed_nodes(grid, with_force)
      type(grid_t), intent(inout) :: grid
      logical, intent(in) :: with_force
      integer :: k
      do k = 1, size(grid%fixed) ! (loops in place: zero_fixed's calls were 0.3 % of a Table-2 sweep's time)
         grid%momentum(grid%fixed(k)) = 0.0_dp
         if (with_force) grid%force(grid%fixed(k)) = 0.0_dp
      end do
   end subroutine hold_fixed_nodes

   !> assemble_nodes(grid, .true.) then solve_momentum(grid, dt, .false.), chunk by chunk (a chunk
   !> is solved while its nodes are still in cache): the grid half of a USL or MUSL step.
   !> `ranges` (optional): only the nodes ranges(1, r) .. ranges(2, r) of each column r, for a caller that
   !> knows the other nodes hold zeros and have no shares (bodies on stacked fields: fused_step); each
   !> node's value is the same as when all are solved.
   subroutine assemble_and_solve(grid, dt, ranges)
      type(grid_t), intent(inout) :: grid
      real(dp), intent(in) :: dt
      integer, intent(in), optional :: ranges(:, :)
      integer :: r
      real(dp) :: lightest
      logical :: done
      if (.not. present(ranges)) then
         call solve_small(grid, dt, .true., done)
         if (done) return
      end if
      lightest = huge(1.0_dp)
      call assemble_ends(grid, .true.)
      if (present(ranges)) then
         do r = 1, size(ranges, 2)
            call solve_part(max(ranges(1, r), 0), min(ranges(2, r), grid%elements), lightest)
         end do
      else
         call solve_part(0, grid%elements, lightest)
      end if
      call fix_nodes(grid, lightest)
   contains
      !> Nodes first..last, in node_chunk chunks on threads for a large grid.
      subroutine solve_part(first, last, lightest)
         integer, intent(in) :: first, last
         real(dp), intent(inout) :: lightest
         integer :: c, lo, hi
         if (first > last) return
         if (threaded_nodes(grid)) then
            !$omp parallel do default(shared) private(c, lo, hi) schedule(static) reduction(min:lightest)
            do c = first/node_chunk, last/node_chunk
               lo = max(first, c*node_chunk)
               hi = min(last, (c + 1)*node_chunk - 1)
               call assemble_interior(grid, .true., lo, hi)
               call solve_nodes(grid, dt, .false., lo, hi, lightest)
            end do
            !$omp end parallel do
         else
            call assemble_interior(grid, .true., first, last)
            call solve_nodes(grid, dt, .false., first, last, lightest)
         end if
      end subroutine solve_part
   end subroutine assemble_and_solve

   !> A grid of at most small_nodes elements without external loads: assemble_and_solve (with_nodes) or
   !> solve_momentum with its force (not) in one call over its nodes (assemble_solve_serial) and `done`;
   !> else nothing and not `done`.
   subroutine solve_small(grid, dt, with_nodes, done)
      type(grid_t), intent(inout) :: grid
      real(dp), intent(in) :: dt
      logical, intent(in) :: with_nodes
      logical, intent(out) :: done
      real(dp) :: lightest
      done = grid%elements <= small_nodes .and. .not. loaded(grid)
      if (.not. done) return
      lightest = huge(1.0_dp)
      call assemble_solve_serial(with_nodes, grid%elements, dt, grid%inv_dx, grid%empty_mass, grid%element_mass_left, &
                                 grid%element_mass_right, grid%element_momentum_left, grid%element_momentum_right, &
                                 grid%element_stress_volume, grid%mass, grid%momentum, grid%force, grid%acceleration, &
                                 grid%velocity, lightest)
      call fix_nodes(grid, lightest)
   end subroutine solve_small

   !> assemble_and_solve (with_nodes) or solve_momentum with the force (not) of a grid of n elements without
   !> external loads (solve_small): each node's mass and momentum (with_nodes) and internal force from its
   !> elements' shares (the end nodes from their one element), then its update as solve_range makes it
   !> (the same operations, in the same order: node 0, the interior, node n). One loop over the nodes, on
   !> explicit-shape arrays: on the small runs of a sweep (1-50 elements) the calls and loop set-ups of the
   !> ends, the interior and the update were about a third of the grid's work.
   subroutine assemble_solve_serial(with_nodes, n, dt, inv_dx, empty_mass, mass_left, mass_right, momentum_left, &
                                    momentum_right, stress_volume, mass, momentum, force, acceleration, velocity, lightest)
      !> whether the nodes' mass and momentum are assembled here (else they are, and only the force is)
      logical, intent(in) :: with_nodes
      integer, intent(in) :: n
      real(dp), intent(in) :: dt, inv_dx, empty_mass
      real(dp), intent(in) :: mass_left(n), mass_right(n), momentum_left(n), momentum_right(n), stress_volume(n)
      real(dp), intent(inout) :: mass(0:n), momentum(0:n), force(0:n), acceleration(0:n), velocity(0:n)
      real(dp), intent(inout) :: lightest
      integer :: i
      real(dp) :: lowest
      lowest = lightest
      if (with_nodes) then
         mass(0) = mass_left(1)
         momentum(0) = momentum_left(1)
      end if
      force(0) = stress_volume(1)*inv_dx
      call update_node(dt, empty_mass, mass(0), force(0), momentum(0), acceleration(0), velocity(0), lowest)
      do i = 1, n - 1
         if (with_nodes) then
            mass(i) = mass_right(i) + mass_left(i + 1)
            momentum(i) = momentum_right(i) + momentum_left(i + 1)
         end if
         force(i) = (stress_volume(i + 1) - stress_volume(i))*inv_dx
         call update_node(dt, empty_mass, mass(i), force(i), momentum(i), acceleration(i), velocity(i), lowest)
      end do
      if (with_nodes) then
         mass(n) = mass_right(n)
         momentum(n) = momentum_right(n)
      end if
      force(n) = -stress_volume(n)*inv_dx
      call update_node(dt, empty_mass, mass(n), force(n), momentum(n), acceleration(n), velocity(n), lowest)
      lightest = lowest
   end subroutine assemble_solve_serial

   !> The end nodes 0 and `elements` of the domain (each has one element).
   subroutine assemble_ends(grid, with_force)
      type(grid_t), intent(inout) :: grid
      logical, intent(in) :: with_force
      integer :: n
      n = grid%elements
      grid%mass(0) = grid%element_mass_left(1)
      grid%mass(n) = grid%element_mass_right(n)
      grid%momentum(0) = grid%element_momentum_left(1)
      grid%momentum(n) = grid%element_momentum_right(n)
      if (with_force) call force_ends(grid)
   end subroutine assemble_ends

   !> Internal force on the end nodes of the domain, from their one element each (dN = -1/dx on an
   !> element's left node, +1/dx on its right node).
   !> Then the external loads on them (external_loads).
   subroutine force_ends(grid)
      type(grid_t), intent(inout) :: grid
      grid%force(0) = grid%element_stress_volume(1)*grid%inv_dx
      grid%force(grid%elements) = -grid%element_stress_volume(grid%elements)*grid%inv_dx
      if (.not. loaded(grid)) return
      call external_loads(grid, 0, 0)
      call external_loads(grid, grid%elements, grid%elements)
   end subroutine force_ends

   !> Whether the run's passes scatter per-particle external forces: allocate the element shares
   !> they scatter into (once).
   subroutine element_forces(grid)
      type(grid_t), intent(inout) :: grid
      if (allocated(grid%element_force_left)) return
      allocate (grid%element_force_left(grid%elements), grid%element_force_right(grid%elements))
      grid%element_force_left = 0.0_dp
      grid%element_force_right = 0.0_dp
   end subroutine element_forces

   !> The external loads on nodes lo..hi, once their internal force, mass and momentum are
   !> assembled: the element shares of per-particle forces (right share of the left element first, as
   !> for the other shares), the uniform body acceleration, the driven node. Nothing when the run has none.
   subroutine external_loads(grid, lo, hi)
      type(grid_t), intent(inout) :: grid
      integer, intent(in) :: lo, hi
      integer :: i
      if (allocated(grid%element_force_left)) then
         do i = lo, hi
            if (i >= 1) grid%force(i) = grid%force(i) + grid%element_force_right(i)
            if (i < grid%elements) grid%force(i) = grid%force(i) + grid%element_force_left(i + 1)
         end do
      end if
      if (grid%loads%acceleration /= 0.0_dp) call accelerate_range(lo, hi, grid%loads%acceleration, grid%mass, grid%force)
      associate (d => grid%loads%driven_node)
         if (d >= lo .and. d <= hi) grid%force(d) = (grid%mass(d)*grid%loads%drive_velocity - grid%momentum(d))/ &
                                                    grid%loads%drive_dt
      end associate
   end subroutine external_loads

   !> Whether the grid has external loads (external_loads does something): tested before calling it, a
   !> call per step and end node for nothing was 0.3 % of the paper's Table-2 sweeps.
   pure logical function loaded(grid)
      type(grid_t), intent(in) :: grid
      loaded = allocated(grid%element_force_left) .or. grid%loads%acceleration /= 0.0_dp .or. &
               grid%loads%driven_node >= 0
   end function loaded

   !> f_I += m_I a on nodes lo..hi (the same expression as a scene's add_forces: f - (-a) m_I rounds as f + a m_I).
   subroutine accelerate_range(lo, hi, acceleration, mass, force)
      integer, intent(in) :: lo, hi
      real(dp), intent(in) :: acceleration
      real(dp), intent(in), contiguous :: mass(0:)
      real(dp), intent(inout), contiguous :: force(0:)
      integer :: i
      do i = lo, hi
         force(i) = force(i) + acceleration*mass(i)
      end do
   end subroutine accelerate_range

   !> The interior nodes among i0..i1: each sums the shares of its two elements (left element first).
   subroutine assemble_interior(grid, with_force, i0, i1)
      type(grid_t), intent(inout) :: grid
      logical, intent(in) :: with_force
      integer, intent(in) :: i0, i1
      integer :: lo, hi
      lo = max(i0, 1)
      hi = min(i1, grid%elements - 1)
      call assemble_range(lo, hi, grid%element_mass_left, grid%element_mass_right, grid%element_momentum_left, &
                          grid%element_momentum_right, grid%mass, grid%momentum)
      if (with_force) then
         call force_range(lo, hi, grid%inv_dx, grid%element_stress_volume, grid%force)
         if (loaded(grid)) call external_loads(grid, lo, hi)
      end if
   end subroutine assemble_interior

   subroutine assemble_range(lo, hi, mass_left, mass_right, momentum_left, momentum_right, mass, momentum)
      integer, intent(in) :: lo, hi
      real(dp), intent(in), contiguous :: mass_left(:), mass_right(:), momentum_left(:), momentum_right(:)
      real(dp), intent(inout), contiguous :: mass(0:), momentum(0:)
      integer :: i
      do i = lo, hi
         mass(i) = mass_right(i) + mass_left(i + 1)
         momentum(i) = momentum_right(i) + momentum_left(i + 1)
      end do
   end subroutine assemble_range

   !> f_I = -sum_p dN_I(x_p) sigma_p V_p with dN = -1/dx (left node), +1/dx (right node).
   subroutine force_range(lo, hi, inv_dx, stress_volume, force)
      integer, intent(in) :: lo, hi
      real(dp), intent(in) :: inv_dx
      real(dp), intent(in), contiguous :: stress_volume(:)
      real(dp), intent(inout), contiguous :: force(0:)
      integer :: i
      do i = lo, hi
         force(i) = (stress_volume(i + 1) - stress_volume(i))*inv_dx
      end do
   end subroutine force_range

   !> assemble_nodes(grid, .false.) then nodal_velocity(grid); a grid that one thread updates in one call
   !> over its nodes (kinematics_serial: each node's mass, momentum and velocity by the same operations),
   !> the fixed nodes' momentum and velocity zero after it.
   subroutine nodal_kinematics(grid)
      type(grid_t), intent(inout) :: grid
      integer :: k
      if (threaded_nodes(grid)) then
         call assemble_nodes(grid, .false.)
         call nodal_velocity(grid)
         return
      end if
      call kinematics_serial(grid%elements, grid%empty_mass, grid%element_mass_left, grid%element_mass_right, &
                             grid%element_momentum_left, grid%element_momentum_right, grid%mass, grid%momentum, &
                             grid%velocity)
      do k = 1, size(grid%fixed)
         grid%momentum(grid%fixed(k)) = 0.0_dp
         grid%velocity(grid%fixed(k)) = 0.0_dp
      end do
   end subroutine nodal_kinematics

   subroutine kinematics_serial(n, empty_mass, mass_left, mass_right, momentum_left, momentum_right, mass, momentum, &
                                velocity)
      integer, intent(in) :: n
      real(dp), intent(in) :: empty_mass
      real(dp), intent(in) :: mass_left(n), mass_right(n), momentum_left(n), momentum_right(n)
      real(dp), intent(inout) :: mass(0:n), momentum(0:n), velocity(0:n)
      mass(0) = mass_left(1)
      momentum(0) = momentum_left(1)
      mass(n) = mass_right(n)
      momentum(n) = momentum_right(n)
      call assemble_range(1, n - 1, mass_left, mass_right, momentum_left, momentum_right, mass, momentum)
      call velocity_range(0, n, empty_mass, mass, momentum, velocity)
   end subroutine kinematics_serial

   !> v_I = p_I / m_I (zero on empty nodes and on the fixed nodes).
   subroutine nodal_velocity(grid)
      type(grid_t), intent(inout) :: grid
      integer :: k
      if (threaded_nodes(grid)) then
         !$omp parallel do default(shared) private(k) schedule(static)
         do k = 0, grid%elements/node_chunk
            call velocity_range(k*node_chunk, min(grid%elements, (k + 1)*node_chunk - 1), grid%empty_mass, &
                                grid%mass, grid%momentum, grid%velocity)
         end do
         !$omp end parallel do
      else
         call velocity_range(0, grid%elements, grid%empty_mass, grid%mass, grid%momentum, grid%velocity)
      end if
      do k = 1, size(grid%fixed) ! (see hold_fixed_nodes)
         grid%velocity(grid%fixed(k)) = 0.0_dp
      end do
   end subroutine nodal_velocity

   subroutine velocity_range(lo, hi, empty_mass, mass, momentum, velocity)
      integer, intent(in) :: lo, hi
      real(dp), intent(in) :: empty_mass
      real(dp), intent(in), contiguous :: mass(0:), momentum(0:)
      real(dp), intent(inout), contiguous :: velocity(0:)
      integer :: i
      do i = lo, hi
         if (mass(i) > empty_mass) then
            velocity(i) = momentum(i)/mass(i)
         else
            velocity(i) = 0.0_dp
         end if
      end do
   end subroutine velocity_range

   !> Explicit momentum update p_I += dt f_I; a_I = f_I/m_I; v_I = p_I/m_I (the updated velocity).
   !> Requires the nodal mass and momentum from `assemble_nodes`, and the force from
   !> `assemble_nodes(grid, .true.)` unless `with_force` asks to assemble it here.
   subroutine solve_momentum(grid, dt, with_force)
      type(grid_t), intent(inout) :: grid
      real(dp), intent(in) :: dt
      logical, intent(in) :: with_force
      integer :: k
      real(dp) :: lightest
      logical :: done
      if (with_force) then
         call solve_small(grid, dt, .false., done)
         if (done) return
      end if
      lightest = huge(1.0_dp)
      if (with_force) call force_ends(grid)
      if (threaded_nodes(grid)) then
         !$omp parallel do default(shared) private(k) schedule(static) reduction(min:lightest)
         do k = 0, grid%elements/node_chunk
            call solve_nodes(grid, dt, with_force, k*node_chunk, min(grid%elements, (k + 1)*node_chunk - 1), lightest)
         end do
         !$omp end parallel do
      else
         call solve_nodes(grid, dt, with_force, 0, grid%elements, lightest)
      end if
      call fix_nodes(grid, lightest)
   end subroutine solve_momentum

   !> solve_momentum on nodes i0..i1 (the interior ones' force first, when `with_force`);
   !> `lightest` takes the smallest positive nodal mass met (empty margin nodes have none).
   subroutine solve_nodes(grid, dt, with_force, i0, i1, lightest)
      type(grid_t), intent(inout) :: grid
      real(dp), intent(in) :: dt
      logical, intent(in) :: with_force
      integer, intent(in) :: i0, i1
      real(dp), intent(inout) :: lightest
      if (with_force) then
         call force_range(max(i0, 1), min(i1, grid%elements - 1), grid%inv_dx, grid%element_stress_volume, grid%force)
         if (loaded(grid)) call external_loads(grid, max(i0, 1), min(i1, grid%elements - 1))
      end if
      call solve_range(i0, i1, dt, grid%empty_mass, grid%mass, grid%force, grid%momentum, grid%acceleration, &
                       grid%velocity, lightest)
   end subroutine solve_nodes

   !> The nodal update of nodes lo..hi (also the generic path's): p += dt f, a = f/m, v = p/m, empty
   !> nodes 0; `lightest` takes the smallest positive mass met.
   subroutine solve_range(lo, hi, dt, empty_mass, mass, force, momentum, acceleration, velocity, lightest)
      integer, intent(in) :: lo, hi
      real(dp), intent(in) :: dt, empty_mass
      real(dp), intent(in), contiguous :: mass(0:), force(0:)
      real(dp), intent(inout), contiguous :: momentum(0:), acceleration(0:), velocity(0:)
      real(dp), intent(inout) :: lightest
      integer :: i
      real(dp) :: lowest
      lowest = lightest ! (a local: gfortran kept the dummy in memory, a store and load per node)
      do i = lo, hi
         call update_node(dt, empty_mass, mass(i), force(i), momentum(i), acceleration(i), velocity(i), lowest)
      end do
      lightest = lowest
   end subroutine solve_range

   !> One node's update: p += dt f, a = f/m, v = p/m (empty nodes 0), and the lightest node with mass so far
   !> in `lowest`.
   pure subroutine update_node(dt, empty_mass, m, f, p, a, v, lowest)
      real(dp), intent(in) :: dt, empty_mass, m, f
      real(dp), intent(inout) :: p, lowest
      real(dp), intent(out) :: a, v
      p = p + dt*f
      if (m > empty_mass) then
         a = f/m
         v = p/m
         lowest = min(lowest, m)
      else ! (one test for the nodes with mass, the common case)
         if (m > 0.0_dp) lowest = min(lowest, m)
         a = 0.0_dp
         v = 0.0_dp
      end if
   end subroutine update_node

   !> The fixed nodes stay at rest; records the lightest node of the step.
   subroutine fix_nodes(grid, lightest)
      type(grid_t), intent(inout) :: grid
      real(dp), intent(in) :: lightest
      integer :: k
      grid%min_node_mass = lightest
      ! one loop over the fixed nodes (four calls of zero_fixed were 0.5 % of the paper's Table-2 sweep)
      do k = 1, size(grid%fixed)
         grid%momentum(grid%fixed(k)) = 0.0_dp
         grid%force(grid%fixed(k)) = 0.0_dp
         grid%acceleration(grid%fixed(k)) = 0.0_dp
         grid%velocity(grid%fixed(k)) = 0.0_dp
      end do
   end subroutine fix_nodes

   !> Zero a nodal field at the fixed nodes. A loop: the array section field(fixed) made gfortran
   !> allocate a temporary at every call (malloc and free were 3 % of the paper's sweep).
   subroutine zero_fixed(fixed, field)
      integer, intent(in), contiguous :: fixed(:)
      real(dp), intent(inout), contiguous :: field(0:)
      integer :: k
      do k = 1, size(fixed)
         field(fixed(k)) = 0.0_dp
      end do
   end subroutine zero_fixed

   !> The grid's fields to or from `state` (under `prefix`.*, as state%saving says), for a checkpoint:
   !> what a step leaves for the next (the fused kernels' element shares, the nodal fields a snapshot
   !> reads), into a grid made for the same run.
   subroutine sync_grid(state, prefix, grid)
      type(state_t), intent(inout) :: state
      character(len=*), intent(in) :: prefix
      type(grid_t), intent(inout) :: grid
      call state%sync(prefix//'.element_mass_left', grid%element_mass_left)
      call state%sync(prefix//'.element_mass_right', grid%element_mass_right)
      call state%sync(prefix//'.element_momentum_left', grid%element_momentum_left)
      call state%sync(prefix//'.element_momentum_right', grid%element_momentum_right)
      call state%sync(prefix//'.element_stress_volume', grid%element_stress_volume)
      call state%sync(prefix//'.element_strain', grid%element_strain)
      call state%sync(prefix//'.element_force_left', grid%element_force_left)
      call state%sync(prefix//'.element_force_right', grid%element_force_right)
      call state%sync(prefix//'.mass', grid%mass)
      call state%sync(prefix//'.momentum', grid%momentum)
      call state%sync(prefix//'.force', grid%force)
      call state%sync(prefix//'.velocity', grid%velocity)
      call state%sync(prefix//'.acceleration', grid%acceleration)
      call state%sync(prefix//'.min_node_mass', grid%min_node_mass)
   end subroutine sync_grid
end module mpm_grid
