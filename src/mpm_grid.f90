!> The background mesh: a uniform 1-D grid of 2-node linear elements on [0, length], lumped
!> mass, node 0 fixed (u = 0 at x = 0), the other end free.
!>
!> Particle-to-grid transfers accumulate per element first (`element_*` arrays: the share of
!> the element's left and right node), then `assemble_nodes` adds the two neighbouring elements'
!> shares in a fixed order. This keeps sums independent of how particles are split between threads.
module mpm_grid
   use mpm_kinds, only: dp
   use mpm_errors, only: error_t, set_error
   use mpm_strings, only: str
   implicit none
   private
   public :: grid_t, grid_init, assemble_nodes, nodal_velocity, solve_momentum, mass_tolerance
   public :: segments_t, share_count

   !> Nodes lighter than this fraction of one particle's mass are treated as empty.
   real(dp), parameter :: mass_tolerance = 1.0e-12_dp

   !> Number of per-element shares a particle pass accumulates (mass left/right, momentum
   !> left/right, stress*volume): the layout of the halo buffers below.
   integer, parameter :: share_count = 5

   !> How the particle passes split one run into segments: contiguous element ranges, fixed by the
   !> problem size only (never by the thread count), each holding a contiguous range of particles
   !> (particles are kept sorted by element). A segment sums the shares of its own elements in particle
   !> order; shares for the element just left or right of its range go to its halo buffers, added in a
   !> fixed order after the pass. So every sum has the same association whatever the number of threads.
   !> Filled by the first P2G (mpm_transfer), used by every later pass; no allocation in the time loop.
   type :: segments_t
      integer :: count = 0
      !> Segment k covers elements first_element(k) .. first_element(k+1)-1.
      integer, allocatable :: first_element(:)
      !> ... and particles first_particle(k) .. first_particle(k+1)-1 (found at the start of a pass).
      integer, allocatable :: first_particle(:)
      !> Shares for element first_element(k)-1 (halo_left) and first_element(k+1) (halo_right).
      real(dp), allocatable :: halo_left(:, :), halo_right(:, :)
      !> Per-segment totals: displacement, kinetic and strain energy; min J; max move and its particle;
      !> first particle outside; first and last new cell; unsorted or far-moving particles met.
      real(dp), allocatable :: sums(:, :), min_volume_ratio(:), max_cell_move(:)
      integer, allocatable :: furthest(:), outside(:), first_cell(:), last_cell(:)
      logical, allocatable :: unsorted(:), far(:)
   end type segments_t

   !> Grid state. Nodes are numbered 0..elements; element e spans nodes e-1 and e.
   type :: grid_t
      integer :: elements = 0
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
      !> Nodal fields, index 0..elements.
      real(dp), allocatable :: mass(:), momentum(:), force(:), velocity(:), acceleration(:)
      !> Smallest nodal mass met by `solve_momentum` in this step (diagnostic of marginal runs).
      real(dp) :: min_node_mass = huge(1.0_dp)
      !> Work split of the particle passes (see segments_t).
      type(segments_t) :: segments
   end type grid_t

contains

   !> Allocate a grid of `elements` elements over [0, length]; `particle_mass` sets the empty-node test.
   subroutine grid_init(grid, elements, length, particle_mass, error)
      type(grid_t), intent(out) :: grid
      integer, intent(in) :: elements
      real(dp), intent(in) :: length, particle_mass
      type(error_t), allocatable, intent(out) :: error
      integer :: stat
      grid%elements = elements
      grid%length = length
      grid%dx = length/elements
      grid%inv_dx = elements/length
      grid%empty_mass = mass_tolerance*particle_mass
      allocate (grid%element_mass_left(elements), grid%element_mass_right(elements), &
                grid%element_momentum_left(elements), grid%element_momentum_right(elements), &
                grid%element_stress_volume(elements), &
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
      grid%mass = 0.0_dp
      grid%momentum = 0.0_dp
      grid%force = 0.0_dp
      grid%velocity = 0.0_dp
      grid%acceleration = 0.0_dp
   end subroutine grid_init

   !> Nodal mass, momentum and (when `with_force`) internal force from the element shares.
   !> The fixed node 0 gets zero momentum and force.
   subroutine assemble_nodes(grid, with_force)
      type(grid_t), intent(inout) :: grid
      logical, intent(in) :: with_force
      integer :: n, i
      n = grid%elements
      grid%mass(0) = grid%element_mass_left(1)
      grid%mass(n) = grid%element_mass_right(n)
      grid%momentum(n) = grid%element_momentum_right(n)
      do i = 1, n - 1
         grid%mass(i) = grid%element_mass_right(i) + grid%element_mass_left(i + 1)
         grid%momentum(i) = grid%element_momentum_right(i) + grid%element_momentum_left(i + 1)
      end do
      grid%momentum(0) = 0.0_dp
      if (with_force) call assemble_force(grid)
   end subroutine assemble_nodes

   !> f_I = -sum_p dN_I(x_p) sigma_p V_p with dN = -1/dx (left node), +1/dx (right node).
   subroutine assemble_force(grid)
      type(grid_t), intent(inout) :: grid
      integer :: n, i
      n = grid%elements
      grid%force(0) = 0.0_dp
      grid%force(n) = -grid%element_stress_volume(n)*grid%inv_dx
      do i = 1, n - 1
         grid%force(i) = (grid%element_stress_volume(i + 1) - grid%element_stress_volume(i))*grid%inv_dx
      end do
   end subroutine assemble_force

   !> v_I = p_I / m_I (zero on empty nodes and on the fixed node).
   subroutine nodal_velocity(grid)
      type(grid_t), intent(inout) :: grid
      integer :: i
      do i = 0, grid%elements
         if (grid%mass(i) > grid%empty_mass) then
            grid%velocity(i) = grid%momentum(i)/grid%mass(i)
         else
            grid%velocity(i) = 0.0_dp
         end if
      end do
      grid%velocity(0) = 0.0_dp
   end subroutine nodal_velocity

   !> Explicit momentum update p_I += dt f_I; a_I = f_I/m_I; v_I = p_I/m_I (the updated velocity).
   !> Requires the force from `assemble_nodes(grid, .true.)` (or `assemble_force`).
   subroutine solve_momentum(grid, dt, with_force)
      type(grid_t), intent(inout) :: grid
      real(dp), intent(in) :: dt
      logical, intent(in) :: with_force
      integer :: i
      if (with_force) call assemble_force(grid)
      grid%min_node_mass = huge(1.0_dp)
      do i = 0, grid%elements
         grid%min_node_mass = min(grid%min_node_mass, grid%mass(i))
         grid%momentum(i) = grid%momentum(i) + dt*grid%force(i)
         if (grid%mass(i) > grid%empty_mass) then
            grid%acceleration(i) = grid%force(i)/grid%mass(i)
            grid%velocity(i) = grid%momentum(i)/grid%mass(i)
         else
            grid%acceleration(i) = 0.0_dp
            grid%velocity(i) = 0.0_dp
         end if
      end do
      grid%momentum(0) = 0.0_dp
      grid%acceleration(0) = 0.0_dp
      grid%velocity(0) = 0.0_dp
   end subroutine solve_momentum
end module mpm_grid
