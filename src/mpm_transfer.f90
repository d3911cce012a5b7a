!> Particle <-> grid transfers with linear shape functions, written as fused passes over the
!> particles: each pass reads and writes every particle once, so a time step costs one or two
!> sweeps through particle memory instead of four or five. Each scheme composes these passes
!> (see mpm_scheme_*). Every pass accumulates the per-step totals the diagnostics and guards need.
!>
!> Notation: a particle in element e with local coordinate xi has N_left = 1 - xi on node e-1 and
!> N_right = xi on node e; dN = -/+ 1/dx. Grid nodal arrays are indexed 0..elements.
!>
!> Speed (see studies/benchmark): the per-particle arithmetic (locate, shape functions, elastic
!> update) is written out here rather than called from mpm_shape / mpm_material, because gfortran does
!> not inline across modules without LTO; the expressions are the same, operation for operation.
!> (A same-module helper for the cell lookup, replacing its four written-out copies, measured 19 %
!> slower on the paper's sweep: it is not inlined into these large loops. The copies stay.)
!> Particles stay sorted by element, so consecutive particles scatter into the same element: the
!> element shares are summed in registers while the element does not change and written once per
!> run of particles ("flush"), instead of a store-to-load chain through memory for every particle.
!>
!> Threads: a large run (at least `parallel_threshold` particles) is cut into segments of whole
!> elements whose size depends on the problem only (see segments_t in mpm_grid); the segments of a
!> pass run in an OpenMP loop, unless the caller is already inside a parallel region (a sweep), where
!> the same segments run one after the other. Every sum is therefore associated the same way whatever
!> the number of threads (and whichever thread runs a segment: the loop is scheduled dynamically, so
!> that a core shared with other work does not hold the other back): results are bit-for-bit
!> identical with 1, 2 or more threads.
module mpm_transfer
   use omp_lib, only: omp_in_parallel
   use mpm_kinds, only: dp
   use mpm_grid, only: grid_t, segments_t, share_count
   use mpm_particles, only: particles_t
   implicit none
   private
   integer, parameter :: pass_usf_move = 1, pass_usf_stress = 2, pass_usl = 3, pass_musl_remap = 4, &
                         pass_musl_stress = 5
   public :: pass_totals_t, clear_element_shares, merge_totals
   public :: p2g, g2p_then_p2g, stress_then_force, g2p_stress_then_p2g, g2p_with_remap, stress_then_p2g
   public :: parallel_threshold, segment_particles

   !> Runs with fewer particles are one segment: a pass then costs a few microseconds, less than
   !> waking a second thread is worth.
   integer, parameter :: parallel_threshold = 100000
   !> Target number of particles per segment of a large run: small enough for an even split between
   !> threads, large enough that the per-segment bookkeeping is negligible.
   integer, parameter :: segment_particles = 8192

   !> Which element shares a pass scatters (bit set).
   integer, parameter :: share_mass = 1, share_momentum = 2, share_stress = 4

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
   !> Also plans the segments of the run and sorts the particles by element when they are not.
   !> Runs on one thread (it is called once per run).
   subroutine p2g(particles, grid, with_stress, totals)
      type(particles_t), intent(inout) :: particles
      type(grid_t), intent(inout) :: grid
      logical, intent(in) :: with_stress
      type(pass_totals_t), intent(out) :: totals
      integer :: p, c, cur, elements
      real(dp) :: s, xi, n0, n1, m, vp, sv, a1, a2, a3, a4, a5
      logical :: sorted
      call clear_element_shares(grid, .true., with_stress)
      call plan_segments(grid, particles%count)
      m = particles%mass
      elements = grid%elements
      sorted = .true.
      cur = 0
      a1 = 0; a2 = 0; a3 = 0; a4 = 0; a5 = 0
      do p = 1, particles%count
         s = particles%x(p)*grid%inv_dx
         if (s >= 0.0_dp .and. s < real(elements, dp)) then
            c = int(s) + 1
            xi = s - (c - 1)
         else if (s == real(elements, dp)) then
            c = elements
            xi = 1.0_dp
         else
            if (totals%outside == 0) totals%outside = p
            cycle
         end if
         particles%cell(p) = c
         if (c /= cur) then
            if (cur /= 0) call add_shares(grid, cur, a1, a2, a3, a4, a5, with_stress)
            if (c < cur) sorted = .false.
            cur = c
            a1 = 0; a2 = 0; a3 = 0; a4 = 0; a5 = 0
         end if
         n0 = 1.0_dp - xi
         n1 = xi
         vp = particles%v(p)
         a1 = a1 + n0*m
         a2 = a2 + n1*m
         a3 = a3 + n0*m*vp
         a4 = a4 + n1*m*vp
         if (with_stress) then
            sv = particles%stress(p)*particles%volume_ratio(p)*particles%volume0
            a5 = a5 + sv
         end if
         totals%kinetic_energy = totals%kinetic_energy + 0.5_dp*m*vp**2
         totals%min_volume_ratio = min(totals%min_volume_ratio, particles%volume_ratio(p))
      end do
      if (cur /= 0) call add_shares(grid, cur, a1, a2, a3, a4, a5, with_stress)
      if (.not. sorted .and. grid%segments%count > 1 .and. totals%outside == 0) call sort_by_cell(particles, grid)
   contains
      subroutine add_shares(grid, e, a1, a2, a3, a4, a5, with_stress)
         type(grid_t), intent(inout) :: grid
         integer, intent(in) :: e
         real(dp), intent(in) :: a1, a2, a3, a4, a5
         logical, intent(in) :: with_stress
         grid%element_mass_left(e) = grid%element_mass_left(e) + a1
         grid%element_mass_right(e) = grid%element_mass_right(e) + a2
         grid%element_momentum_left(e) = grid%element_momentum_left(e) + a3
         grid%element_momentum_right(e) = grid%element_momentum_right(e) + a4
         if (with_stress) grid%element_stress_volume(e) = grid%element_stress_volume(e) + a5
      end subroutine add_shares
   end subroutine p2g

   !> USF, second half: grid-to-particle update with the solved grid (v_p += dt sum N a_I,
   !> x_p += dt sum N v_I), then mass and momentum of the moved particles to the grid for the next step.
   subroutine g2p_then_p2g(particles, grid, dt, totals)
      type(particles_t), intent(inout) :: particles
      type(grid_t), intent(inout) :: grid
      real(dp), intent(in) :: dt
      type(pass_totals_t), intent(out) :: totals
      call prepare_pass(particles, grid)
      call over_segments(particles, grid, pass_usf_move, dt, 0.0_dp)
      call finish_pass(particles, grid, share_mass + share_momentum, .true., totals)
   end subroutine g2p_then_p2g

   !> USF, first half: stress update from the nodal velocities of this step's mapping
   !> (d eps = dt sum dN v_I), then the element shares of stress*volume for the internal force.
   subroutine stress_then_force(particles, grid, dt, youngs_modulus, totals)
      type(particles_t), intent(inout) :: particles
      type(grid_t), intent(inout) :: grid
      real(dp), intent(in) :: dt, youngs_modulus
      type(pass_totals_t), intent(out) :: totals
      call prepare_pass(particles, grid)
      call over_segments(particles, grid, pass_usf_stress, dt, youngs_modulus)
      call finish_pass(particles, grid, share_stress, .false., totals)
   end subroutine stress_then_force

   !> USL in one pass: grid-to-particle update, stress update from the updated nodal velocities,
   !> then mass, momentum and stress*volume of the moved particles to the grid for the next step.
   subroutine g2p_stress_then_p2g(particles, grid, dt, youngs_modulus, totals)
      type(particles_t), intent(inout) :: particles
      type(grid_t), intent(inout) :: grid
      real(dp), intent(in) :: dt, youngs_modulus
      type(pass_totals_t), intent(out) :: totals
      call prepare_pass(particles, grid)
      call over_segments(particles, grid, pass_usl, dt, youngs_modulus)
      call finish_pass(particles, grid, share_mass + share_momentum + share_stress, .true., totals)
   end subroutine g2p_stress_then_p2g

   !> MUSL, first pass: grid-to-particle update, and the updated particle momentum mapped back to
   !> the grid with the same (start-of-step) shape functions. Mass shares are unchanged.
   subroutine g2p_with_remap(particles, grid, dt, totals)
      type(particles_t), intent(inout) :: particles
      type(grid_t), intent(inout) :: grid
      real(dp), intent(in) :: dt
      type(pass_totals_t), intent(out) :: totals
      call prepare_pass(particles, grid)
      call over_segments(particles, grid, pass_musl_remap, dt, 0.0_dp)
      call finish_pass(particles, grid, share_momentum, .false., totals)
   end subroutine g2p_with_remap

   !> MUSL, second pass: stress update from the remapped nodal velocities (start-of-step cell),
   !> then mass, momentum and stress*volume at the new positions for the next step.
   subroutine stress_then_p2g(particles, grid, dt, youngs_modulus, totals)
      type(particles_t), intent(inout) :: particles
      type(grid_t), intent(inout) :: grid
      real(dp), intent(in) :: dt, youngs_modulus
      type(pass_totals_t), intent(out) :: totals
      call prepare_pass(particles, grid)
      call over_segments(particles, grid, pass_musl_stress, dt, youngs_modulus)
      call finish_pass(particles, grid, share_mass + share_momentum + share_stress, .true., totals)
   end subroutine stress_then_p2g

   !> Run pass `kind` over every segment: on OpenMP threads when the run has several segments and
   !> is not itself inside a parallel region (a sweep), else in this thread. A branch, not an `if`
   !> clause: an inactive parallel region still costs a team set-up (about a microsecond) per pass,
   !> which dominated small runs.
   subroutine over_segments(particles, grid, kind, dt, youngs_modulus)
      type(particles_t), intent(inout) :: particles
      type(grid_t), intent(inout) :: grid
      integer, intent(in) :: kind
      real(dp), intent(in) :: dt, youngs_modulus
      integer :: k
      if (grid%segments%count > 1 .and. .not. omp_in_parallel()) then
         !$omp parallel do default(shared) private(k) schedule(dynamic, 4)
         do k = 1, grid%segments%count
            call segment(k)
         end do
         !$omp end parallel do
      else
         do k = 1, grid%segments%count
            call segment(k)
         end do
      end if
   contains
      subroutine segment(k)
         integer, intent(in) :: k
         select case (kind)
         case (pass_usf_move)
            call usf_move_segment(k, grid%segments, particles%x, particles%x0, particles%v, particles%cell, &
                                  grid%acceleration, grid%velocity, grid%element_mass_left, grid%element_mass_right, &
                                  grid%element_momentum_left, grid%element_momentum_right, &
                                  grid%elements, grid%inv_dx, dt, particles%mass)
         case (pass_usf_stress)
            call usf_stress_segment(k, grid%segments, particles%stress, particles%volume_ratio, particles%cell, &
                                    grid%velocity, grid%element_stress_volume, grid%inv_dx, dt, youngs_modulus, &
                                    particles%volume0)
         case (pass_usl)
            call usl_segment(k, grid%segments, particles%x, particles%x0, particles%v, particles%stress, &
                             particles%volume_ratio, particles%cell, grid%acceleration, grid%velocity, &
                             grid%element_mass_left, grid%element_mass_right, grid%element_momentum_left, &
                             grid%element_momentum_right, grid%element_stress_volume, &
                             grid%elements, grid%inv_dx, dt, youngs_modulus, particles%mass, particles%volume0)
         case (pass_musl_remap)
            call musl_remap_segment(k, grid%segments, particles%x, particles%x0, particles%v, particles%cell, &
                                    grid%acceleration, grid%velocity, grid%element_momentum_left, &
                                    grid%element_momentum_right, grid%inv_dx, dt, particles%mass)
         case (pass_musl_stress)
            call musl_stress_segment(k, grid%segments, particles%x, particles%v, particles%stress, &
                                     particles%volume_ratio, particles%cell, grid%velocity, &
                                     grid%element_mass_left, grid%element_mass_right, grid%element_momentum_left, &
                                     grid%element_momentum_right, grid%element_stress_volume, &
                                     grid%elements, grid%inv_dx, dt, youngs_modulus, particles%mass, particles%volume0)
         end select
      end subroutine segment
   end subroutine over_segments

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

   ! ---- segments: planning, particle ranges, and what follows the parallel loop ----

   !> Cut the run into segments of whole elements, about `segment_particles` particles each
   !> (one segment below `parallel_threshold`). Allocates only when the plan changes size.
   subroutine plan_segments(grid, count)
      type(grid_t), intent(inout) :: grid
      integer, intent(in) :: count
      integer :: per, n, k
      if (count < parallel_threshold .or. grid%elements < 2) then
         per = grid%elements
      else
         per = max(1, nint(real(segment_particles, dp)*grid%elements/count))
      end if
      n = (grid%elements + per - 1)/per
      associate (seg => grid%segments)
         if (seg%count /= n .or. .not. allocated(seg%first_element)) then
            if (allocated(seg%first_element)) deallocate (seg%first_element, seg%first_particle, seg%halo_left, &
                                                          seg%halo_right, seg%sums, seg%min_volume_ratio, &
                                                          seg%max_cell_move, seg%furthest, seg%outside, &
                                                          seg%first_cell, seg%last_cell, seg%unsorted, seg%far)
            allocate (seg%first_element(n + 1), seg%first_particle(n + 1), seg%halo_left(share_count, n), &
                      seg%halo_right(share_count, n), seg%sums(3, n), seg%min_volume_ratio(n), &
                      seg%max_cell_move(n), seg%furthest(n), seg%outside(n), seg%first_cell(n), &
                      seg%last_cell(n), seg%unsorted(n), seg%far(n))
         end if
         seg%count = n
         seg%first_element = [(min(1 + (k - 1)*per, grid%elements + 1), k=1, n + 1)]
         seg%first_element(n + 1) = grid%elements + 1
      end associate
   end subroutine plan_segments

   !> Segments planned (when a pass comes before any P2G) and particle ranges found.
   subroutine prepare_pass(particles, grid)
      type(particles_t), intent(in) :: particles
      type(grid_t), intent(inout) :: grid
      if (grid%segments%count == 0) call plan_segments(grid, particles%count)
      call find_particle_ranges(grid%segments, particles%cell, particles%count)
   end subroutine prepare_pass

   !> Particle range of each segment: particles are sorted by start-of-step cell, so the range
   !> starts at the first particle whose cell is at least the segment's first element (binary search).
   subroutine find_particle_ranges(seg, cell, count)
      type(segments_t), intent(inout) :: seg
      integer, intent(in), contiguous :: cell(:)
      integer, intent(in) :: count
      integer :: k, lo, hi, mid
      seg%first_particle(1) = 1
      seg%first_particle(seg%count + 1) = count + 1
      do k = 2, seg%count
         lo = seg%first_particle(k - 1)
         hi = count + 1
         do while (lo < hi)
            mid = lo + (hi - lo)/2
            if (cell(mid) < seg%first_element(k)) then
               lo = mid + 1
            else
               hi = mid
            end if
         end do
         seg%first_particle(k) = lo
      end do
   end subroutine find_particle_ranges

   !> After the segments of a pass: halo shares added in a fixed order, totals combined in segment
   !> order (strict comparisons keep the first particle, as a single loop would), far movers added,
   !> and the particles re-sorted by element if some overtook others.
   subroutine finish_pass(particles, grid, shares, moved, totals)
      type(particles_t), intent(inout) :: particles
      type(grid_t), intent(inout) :: grid
      integer, intent(in) :: shares
      logical, intent(in) :: moved
      type(pass_totals_t), intent(inout) :: totals
      integer :: k, e
      logical :: sorted, far
      associate (seg => grid%segments)
         sorted = .true.
         far = .false.
         do k = 1, seg%count
            totals%displacement = totals%displacement + seg%sums(1, k)
            totals%kinetic_energy = totals%kinetic_energy + seg%sums(2, k)
            totals%strain_energy = totals%strain_energy + seg%sums(3, k)
            totals%min_volume_ratio = min(totals%min_volume_ratio, seg%min_volume_ratio(k))
            if (seg%max_cell_move(k) > totals%max_cell_move) then
               totals%max_cell_move = seg%max_cell_move(k)
               totals%furthest = seg%furthest(k)
            end if
            if (totals%outside == 0) totals%outside = seg%outside(k)
            if (seg%unsorted(k)) sorted = .false.
            if (seg%far(k)) far = .true.
            if (k > 1) then
               if (seg%last_cell(k - 1) /= 0 .and. seg%first_cell(k) /= 0 .and. &
                   seg%first_cell(k) < seg%last_cell(k - 1)) sorted = .false.
               e = seg%first_element(k)
               call add_share_set(grid, e - 1, seg%halo_left(:, k), shares)
               call add_share_set(grid, e, seg%halo_right(:, k - 1), shares)
            end if
         end do
         if (far) call add_far_movers(particles, grid, shares)
         if (moved .and. .not. sorted .and. seg%count > 1 .and. totals%outside == 0) then
            call sort_by_cell(particles, grid, totals%furthest)
         end if
      end associate
   end subroutine finish_pass

   subroutine add_share_set(grid, e, a, shares)
      type(grid_t), intent(inout) :: grid
      integer, intent(in) :: e, shares
      real(dp), intent(in) :: a(share_count)
      if (iand(shares, share_mass) /= 0) then
         grid%element_mass_left(e) = grid%element_mass_left(e) + a(1)
         grid%element_mass_right(e) = grid%element_mass_right(e) + a(2)
      end if
      if (iand(shares, share_momentum) /= 0) then
         grid%element_momentum_left(e) = grid%element_momentum_left(e) + a(3)
         grid%element_momentum_right(e) = grid%element_momentum_right(e) + a(4)
      end if
      if (iand(shares, share_stress) /= 0) grid%element_stress_volume(e) = grid%element_stress_volume(e) + a(5)
   end subroutine add_share_set

   !> Particles that moved more than one element past their segment (the cell-crossing guard stops
   !> such a run after this step): their shares, from their new state, in particle order.
   subroutine add_far_movers(particles, grid, shares)
      type(particles_t), intent(inout) :: particles
      type(grid_t), intent(inout) :: grid
      integer, intent(in) :: shares
      integer :: k, p, c, lo, hi
      real(dp) :: xi, m, a(share_count)
      m = particles%mass
      associate (seg => grid%segments)
         do k = 1, seg%count
            if (.not. seg%far(k)) cycle
            lo = seg%first_element(k)
            hi = seg%first_element(k + 1) - 1
            do p = seg%first_particle(k), seg%first_particle(k + 1) - 1
               c = particles%cell(p)
               if (c >= lo - 1 .and. c <= hi + 1) cycle
               xi = particles%x(p)*grid%inv_dx - (c - 1)
               a(1) = (1.0_dp - xi)*m
               a(2) = xi*m
               a(3) = (1.0_dp - xi)*m*particles%v(p)
               a(4) = xi*m*particles%v(p)
               a(5) = particles%stress(p)*particles%volume_ratio(p)*particles%volume0
               call add_share_set(grid, c, a, shares)
            end do
         end do
      end associate
   end subroutine add_far_movers

   !> Stable counting sort of the particles by cell (rare: only when particles overtake each other
   !> across an element boundary, which the bar never does). Allocates its work arrays here.
   !> `furthest`, when given, follows its particle to the new index.
   subroutine sort_by_cell(particles, grid, furthest)
      type(particles_t), intent(inout) :: particles
      type(grid_t), intent(in) :: grid
      integer, intent(inout), optional :: furthest
      integer, allocatable :: next(:), destination(:), icopy(:)
      real(dp), allocatable :: copy(:)
      integer :: p, c, n
      n = particles%count
      allocate (next(grid%elements + 1), destination(n))
      next = 0
      do p = 1, n
         c = particles%cell(p)
         next(c + 1) = next(c + 1) + 1
      end do
      next(1) = 1
      do c = 2, grid%elements + 1
         next(c) = next(c) + next(c - 1)
      end do
      do p = 1, n
         c = particles%cell(p)
         destination(p) = next(c)
         next(c) = next(c) + 1
      end do
      allocate (copy(n))
      call permute(particles%x)
      call permute(particles%x0)
      call permute(particles%v)
      call permute(particles%stress)
      call permute(particles%volume_ratio)
      deallocate (copy)
      allocate (icopy(n))
      icopy(destination) = particles%cell
      particles%cell = icopy
      if (present(furthest)) then
         if (furthest >= 1 .and. furthest <= n) furthest = destination(furthest)
      end if
   contains
      subroutine permute(a)
         real(dp), intent(inout), contiguous :: a(:)
         copy(destination) = a
         a = copy
      end subroutine permute
   end subroutine sort_by_cell

   ! ---- the segment kernels: one segment's particles, its own elements, its halo ----

   !> Add the running shares a1..a5 of element `c` to the grid (own element) or to the halo
   !> (neighbour segment's element); elements further away mark the segment for add_far_movers.
   pure subroutine flush_shares(k, c, lo, hi, shares, a1, a2, a3, a4, a5, mass_left, mass_right, &
                                momentum_left, momentum_right, stress_volume, seg)
      integer, intent(in) :: k, c, lo, hi, shares
      real(dp), intent(in) :: a1, a2, a3, a4, a5
      real(dp), intent(inout), contiguous :: mass_left(:), mass_right(:), momentum_left(:), momentum_right(:), stress_volume(:)
      type(segments_t), intent(inout) :: seg
      if (c >= lo .and. c <= hi) then
         if (iand(shares, share_mass) /= 0) then
            mass_left(c) = mass_left(c) + a1
            mass_right(c) = mass_right(c) + a2
         end if
         if (iand(shares, share_momentum) /= 0) then
            momentum_left(c) = momentum_left(c) + a3
            momentum_right(c) = momentum_right(c) + a4
         end if
         if (iand(shares, share_stress) /= 0) stress_volume(c) = stress_volume(c) + a5
      else if (c == lo - 1) then
         seg%halo_left(:, k) = seg%halo_left(:, k) + [a1, a2, a3, a4, a5]
      else if (c == hi + 1) then
         seg%halo_right(:, k) = seg%halo_right(:, k) + [a1, a2, a3, a4, a5]
      else
         seg%far(k) = .true.
      end if
   end subroutine flush_shares

   !> Segment bookkeeping at the start of a kernel: clear its own elements' shares and its halo.
   pure subroutine open_segment(k, shares, seg, mass_left, mass_right, momentum_left, momentum_right, stress_volume, &
                                first, last, lo, hi)
      integer, intent(in) :: k, shares
      type(segments_t), intent(inout) :: seg
      real(dp), intent(inout), contiguous :: mass_left(:), mass_right(:), momentum_left(:), momentum_right(:), stress_volume(:)
      integer, intent(out) :: first, last, lo, hi
      first = seg%first_particle(k)
      last = seg%first_particle(k + 1) - 1
      lo = seg%first_element(k)
      hi = seg%first_element(k + 1) - 1
      if (iand(shares, share_mass) /= 0) then
         mass_left(lo:hi) = 0.0_dp
         mass_right(lo:hi) = 0.0_dp
      end if
      if (iand(shares, share_momentum) /= 0) then
         momentum_left(lo:hi) = 0.0_dp
         momentum_right(lo:hi) = 0.0_dp
      end if
      if (iand(shares, share_stress) /= 0) stress_volume(lo:hi) = 0.0_dp
      seg%halo_left(:, k) = 0.0_dp
      seg%halo_right(:, k) = 0.0_dp
      seg%far(k) = .false.
      seg%unsorted(k) = .false.
      seg%first_cell(k) = 0
      seg%last_cell(k) = 0
   end subroutine open_segment

   !> USL: G2P, stress update from the updated nodal velocities, P2G at the new position.
   subroutine usl_segment(k, seg, x, x0, v, stress, volume_ratio, cell, acceleration, velocity, &
                          mass_left, mass_right, momentum_left, momentum_right, stress_volume, &
                          elements, inv_dx, dt, youngs_modulus, m, volume0)
      integer, intent(in) :: k
      type(segments_t), intent(inout) :: seg
      real(dp), intent(inout), contiguous :: x(:), v(:), stress(:), volume_ratio(:)
      real(dp), intent(in), contiguous :: x0(:)
      integer, intent(inout), contiguous :: cell(:)
      real(dp), intent(in), contiguous :: acceleration(0:), velocity(0:)
      real(dp), intent(inout), contiguous :: mass_left(:), mass_right(:), momentum_left(:), momentum_right(:), stress_volume(:)
      integer, intent(in) :: elements
      real(dp), intent(in) :: inv_dx, dt, youngs_modulus, m, volume0
      integer, parameter :: shares = share_mass + share_momentum + share_stress
      integer :: p, e, c, cur, first, last, lo, hi, furthest, outside
      real(dp) :: xi, n0, n1, vp, xp, dxp, s, dstrain, sp, jp, sv, move
      real(dp) :: a1, a2, a3, a4, a5, displacement, kinetic, strain, min_j, max_move
      call open_segment(k, shares, seg, mass_left, mass_right, momentum_left, momentum_right, stress_volume, &
                        first, last, lo, hi)
      displacement = 0; kinetic = 0; strain = 0; min_j = huge(1.0_dp); max_move = 0
      furthest = 0; outside = 0
      cur = 0
      a1 = 0; a2 = 0; a3 = 0; a4 = 0; a5 = 0
      do p = first, last
         e = cell(p)
         ! G2P with the start-of-step shape functions
         xi = x(p)*inv_dx - (e - 1)
         n0 = 1.0_dp - xi
         n1 = xi
         vp = v(p) + dt*(n0*acceleration(e - 1) + n1*acceleration(e))
         dxp = dt*(n0*velocity(e - 1) + n1*velocity(e))
         xp = x(p) + dxp
         v(p) = vp
         x(p) = xp
         displacement = displacement + (xp - x0(p))
         kinetic = kinetic + 0.5_dp*m*vp*vp
         move = abs(dxp)*inv_dx
         if (move > max_move) then
            max_move = move
            furthest = p
         end if
         ! stress update: d eps = dt sum dN v_I over the start-of-step cell
         dstrain = dt*(velocity(e) - velocity(e - 1))*inv_dx
         sp = stress(p) + youngs_modulus*dstrain
         jp = volume_ratio(p)*(1.0_dp + dstrain)
         stress(p) = sp
         volume_ratio(p) = jp
         strain = strain + 0.5_dp*sp*sp*(jp*volume0)/youngs_modulus
         min_j = min(min_j, jp)
         ! P2G at the new position
         s = xp*inv_dx
         if (s >= 0.0_dp .and. s < real(elements, dp)) then
            c = int(s) + 1
            xi = s - (c - 1)
         else if (s == real(elements, dp)) then
            c = elements
            xi = 1.0_dp
         else
            if (outside == 0) outside = p
            cycle
         end if
         if (c /= e) cell(p) = c
         if (c /= cur) then
            if (cur /= 0) call flush_shares(k, cur, lo, hi, shares, a1, a2, a3, a4, a5, mass_left, mass_right, &
                                            momentum_left, momentum_right, stress_volume, seg)
            if (c < cur) seg%unsorted(k) = .true.
            if (cur == 0) seg%first_cell(k) = c
            cur = c
            a1 = 0; a2 = 0; a3 = 0; a4 = 0; a5 = 0
         end if
         n0 = 1.0_dp - xi
         n1 = xi
         sv = sp*jp*volume0
         a1 = a1 + n0*m
         a2 = a2 + n1*m
         a3 = a3 + n0*m*vp
         a4 = a4 + n1*m*vp
         a5 = a5 + sv
      end do
      if (cur /= 0) call flush_shares(k, cur, lo, hi, shares, a1, a2, a3, a4, a5, mass_left, mass_right, &
                                      momentum_left, momentum_right, stress_volume, seg)
      seg%last_cell(k) = cur
      seg%sums(:, k) = [displacement, kinetic, strain]
      seg%min_volume_ratio(k) = min_j
      seg%max_cell_move(k) = max_move
      seg%furthest(k) = furthest
      seg%outside(k) = outside
   end subroutine usl_segment

   !> USF second half: G2P, then mass and momentum at the new position.
   subroutine usf_move_segment(k, seg, x, x0, v, cell, acceleration, velocity, &
                               mass_left, mass_right, momentum_left, momentum_right, elements, inv_dx, dt, m)
      integer, intent(in) :: k
      type(segments_t), intent(inout) :: seg
      real(dp), intent(inout), contiguous :: x(:), v(:)
      real(dp), intent(in), contiguous :: x0(:)
      integer, intent(inout), contiguous :: cell(:)
      real(dp), intent(in), contiguous :: acceleration(0:), velocity(0:)
      real(dp), intent(inout), contiguous :: mass_left(:), mass_right(:), momentum_left(:), momentum_right(:)
      integer, intent(in) :: elements
      real(dp), intent(in) :: inv_dx, dt, m
      integer, parameter :: shares = share_mass + share_momentum
      integer :: p, e, c, cur, first, last, lo, hi, furthest, outside
      real(dp) :: xi, n0, n1, vp, xp, dxp, s, move, unused(1)
      real(dp) :: a1, a2, a3, a4, displacement, kinetic, max_move
      call open_segment(k, shares, seg, mass_left, mass_right, momentum_left, momentum_right, unused, &
                        first, last, lo, hi)
      displacement = 0; kinetic = 0; max_move = 0
      furthest = 0; outside = 0
      cur = 0
      a1 = 0; a2 = 0; a3 = 0; a4 = 0
      do p = first, last
         e = cell(p)
         xi = x(p)*inv_dx - (e - 1)
         n0 = 1.0_dp - xi
         n1 = xi
         vp = v(p) + dt*(n0*acceleration(e - 1) + n1*acceleration(e))
         dxp = dt*(n0*velocity(e - 1) + n1*velocity(e))
         xp = x(p) + dxp
         v(p) = vp
         x(p) = xp
         displacement = displacement + (xp - x0(p))
         kinetic = kinetic + 0.5_dp*m*vp*vp
         move = abs(dxp)*inv_dx
         if (move > max_move) then
            max_move = move
            furthest = p
         end if
         s = xp*inv_dx
         if (s >= 0.0_dp .and. s < real(elements, dp)) then
            c = int(s) + 1
            xi = s - (c - 1)
         else if (s == real(elements, dp)) then
            c = elements
            xi = 1.0_dp
         else
            if (outside == 0) outside = p
            cycle
         end if
         if (c /= e) cell(p) = c
         if (c /= cur) then
            if (cur /= 0) call flush_shares(k, cur, lo, hi, shares, a1, a2, a3, a4, 0.0_dp, mass_left, mass_right, &
                                            momentum_left, momentum_right, unused, seg)
            if (c < cur) seg%unsorted(k) = .true.
            if (cur == 0) seg%first_cell(k) = c
            cur = c
            a1 = 0; a2 = 0; a3 = 0; a4 = 0
         end if
         n0 = 1.0_dp - xi
         n1 = xi
         a1 = a1 + n0*m
         a2 = a2 + n1*m
         a3 = a3 + n0*m*vp
         a4 = a4 + n1*m*vp
      end do
      if (cur /= 0) call flush_shares(k, cur, lo, hi, shares, a1, a2, a3, a4, 0.0_dp, mass_left, mass_right, &
                                      momentum_left, momentum_right, unused, seg)
      seg%last_cell(k) = cur
      seg%sums(:, k) = [displacement, kinetic, 0.0_dp]
      seg%min_volume_ratio(k) = huge(1.0_dp)
      seg%max_cell_move(k) = max_move
      seg%furthest(k) = furthest
      seg%outside(k) = outside
   end subroutine usf_move_segment

   !> USF first half: stress update, then stress*volume of the (unmoved) particles per element.
   subroutine usf_stress_segment(k, seg, stress, volume_ratio, cell, velocity, stress_volume, &
                                 inv_dx, dt, youngs_modulus, volume0)
      integer, intent(in) :: k
      type(segments_t), intent(inout) :: seg
      real(dp), intent(inout), contiguous :: stress(:), volume_ratio(:)
      integer, intent(in), contiguous :: cell(:)
      real(dp), intent(in), contiguous :: velocity(0:)
      real(dp), intent(inout), contiguous :: stress_volume(:)
      real(dp), intent(in) :: inv_dx, dt, youngs_modulus, volume0
      integer, parameter :: shares = share_stress
      integer :: p, e, cur, first, last, lo, hi
      real(dp) :: dstrain, sp, jp, a5, strain, min_j, unused(1)
      call open_segment(k, shares, seg, unused, unused, unused, unused, stress_volume, first, last, lo, hi)
      strain = 0; min_j = huge(1.0_dp)
      cur = 0
      a5 = 0
      dstrain = 0
      do p = first, last
         e = cell(p)
         if (e /= cur) then
            if (cur /= 0) call flush_shares(k, cur, lo, hi, shares, 0.0_dp, 0.0_dp, 0.0_dp, 0.0_dp, a5, &
                                            unused, unused, unused, unused, stress_volume, seg)
            if (cur == 0) seg%first_cell(k) = e
            cur = e
            a5 = 0
            dstrain = dt*(velocity(e) - velocity(e - 1))*inv_dx
         end if
         sp = stress(p) + youngs_modulus*dstrain
         jp = volume_ratio(p)*(1.0_dp + dstrain)
         stress(p) = sp
         volume_ratio(p) = jp
         strain = strain + 0.5_dp*sp*sp*(jp*volume0)/youngs_modulus
         min_j = min(min_j, jp)
         a5 = a5 + sp*jp*volume0
      end do
      if (cur /= 0) call flush_shares(k, cur, lo, hi, shares, 0.0_dp, 0.0_dp, 0.0_dp, 0.0_dp, a5, &
                                      unused, unused, unused, unused, stress_volume, seg)
      seg%last_cell(k) = cur
      seg%sums(:, k) = [0.0_dp, 0.0_dp, strain]
      seg%min_volume_ratio(k) = min_j
      seg%max_cell_move(k) = 0
      seg%furthest(k) = 0
      seg%outside(k) = 0
   end subroutine usf_stress_segment

   !> MUSL first pass: G2P, and the new momentum back to the start-of-step nodes.
   subroutine musl_remap_segment(k, seg, x, x0, v, cell, acceleration, velocity, momentum_left, momentum_right, &
                                 inv_dx, dt, m)
      integer, intent(in) :: k
      type(segments_t), intent(inout) :: seg
      real(dp), intent(inout), contiguous :: x(:), v(:)
      real(dp), intent(in), contiguous :: x0(:)
      integer, intent(in), contiguous :: cell(:)
      real(dp), intent(in), contiguous :: acceleration(0:), velocity(0:)
      real(dp), intent(inout), contiguous :: momentum_left(:), momentum_right(:)
      real(dp), intent(in) :: inv_dx, dt, m
      integer, parameter :: shares = share_momentum
      integer :: p, e, cur, first, last, lo, hi, furthest
      real(dp) :: xi, n0, n1, vp, xp, dxp, mv, move, unused(1)
      real(dp) :: a3, a4, displacement, kinetic, max_move
      call open_segment(k, shares, seg, unused, unused, momentum_left, momentum_right, unused, first, last, lo, hi)
      displacement = 0; kinetic = 0; max_move = 0
      furthest = 0
      cur = 0
      a3 = 0; a4 = 0
      do p = first, last
         e = cell(p)
         xi = x(p)*inv_dx - (e - 1)
         n0 = 1.0_dp - xi
         n1 = xi
         vp = v(p) + dt*(n0*acceleration(e - 1) + n1*acceleration(e))
         dxp = dt*(n0*velocity(e - 1) + n1*velocity(e))
         xp = x(p) + dxp
         v(p) = vp
         x(p) = xp
         displacement = displacement + (xp - x0(p))
         kinetic = kinetic + 0.5_dp*m*vp*vp
         move = abs(dxp)*inv_dx
         if (move > max_move) then
            max_move = move
            furthest = p
         end if
         if (e /= cur) then
            if (cur /= 0) call flush_shares(k, cur, lo, hi, shares, 0.0_dp, 0.0_dp, a3, a4, 0.0_dp, &
                                            unused, unused, momentum_left, momentum_right, unused, seg)
            if (cur == 0) seg%first_cell(k) = e
            cur = e
            a3 = 0; a4 = 0
         end if
         mv = m*vp
         a3 = a3 + n0*mv
         a4 = a4 + n1*mv
      end do
      if (cur /= 0) call flush_shares(k, cur, lo, hi, shares, 0.0_dp, 0.0_dp, a3, a4, 0.0_dp, &
                                      unused, unused, momentum_left, momentum_right, unused, seg)
      seg%last_cell(k) = cur
      seg%sums(:, k) = [displacement, kinetic, 0.0_dp]
      seg%min_volume_ratio(k) = huge(1.0_dp)
      seg%max_cell_move(k) = max_move
      seg%furthest(k) = furthest
      seg%outside(k) = 0
   end subroutine musl_remap_segment

   !> MUSL second pass: stress update with the remapped nodal velocity of the start-of-step cell,
   !> then mass, momentum and stress*volume at the new position.
   subroutine musl_stress_segment(k, seg, x, v, stress, volume_ratio, cell, velocity, &
                                  mass_left, mass_right, momentum_left, momentum_right, stress_volume, &
                                  elements, inv_dx, dt, youngs_modulus, m, volume0)
      integer, intent(in) :: k
      type(segments_t), intent(inout) :: seg
      real(dp), intent(in), contiguous :: x(:), v(:)
      real(dp), intent(inout), contiguous :: stress(:), volume_ratio(:)
      integer, intent(inout), contiguous :: cell(:)
      real(dp), intent(in), contiguous :: velocity(0:)
      real(dp), intent(inout), contiguous :: mass_left(:), mass_right(:), momentum_left(:), momentum_right(:), stress_volume(:)
      integer, intent(in) :: elements
      real(dp), intent(in) :: inv_dx, dt, youngs_modulus, m, volume0
      integer, parameter :: shares = share_mass + share_momentum + share_stress
      integer :: p, e, c, cur, first, last, lo, hi, outside
      real(dp) :: xi, n0, n1, vp, s, dstrain, sp, jp, sv
      real(dp) :: a1, a2, a3, a4, a5, strain, min_j
      call open_segment(k, shares, seg, mass_left, mass_right, momentum_left, momentum_right, stress_volume, &
                        first, last, lo, hi)
      strain = 0; min_j = huge(1.0_dp)
      outside = 0
      cur = 0
      a1 = 0; a2 = 0; a3 = 0; a4 = 0; a5 = 0
      do p = first, last
         e = cell(p)
         dstrain = dt*(velocity(e) - velocity(e - 1))*inv_dx
         sp = stress(p) + youngs_modulus*dstrain
         jp = volume_ratio(p)*(1.0_dp + dstrain)
         stress(p) = sp
         volume_ratio(p) = jp
         strain = strain + 0.5_dp*sp*sp*(jp*volume0)/youngs_modulus
         min_j = min(min_j, jp)
         s = x(p)*inv_dx
         if (s >= 0.0_dp .and. s < real(elements, dp)) then
            c = int(s) + 1
            xi = s - (c - 1)
         else if (s == real(elements, dp)) then
            c = elements
            xi = 1.0_dp
         else
            if (outside == 0) outside = p
            cycle
         end if
         if (c /= e) cell(p) = c
         if (c /= cur) then
            if (cur /= 0) call flush_shares(k, cur, lo, hi, shares, a1, a2, a3, a4, a5, mass_left, mass_right, &
                                            momentum_left, momentum_right, stress_volume, seg)
            if (c < cur) seg%unsorted(k) = .true.
            if (cur == 0) seg%first_cell(k) = c
            cur = c
            a1 = 0; a2 = 0; a3 = 0; a4 = 0; a5 = 0
         end if
         n0 = 1.0_dp - xi
         n1 = xi
         vp = v(p)
         sv = sp*jp*volume0
         a1 = a1 + n0*m
         a2 = a2 + n1*m
         a3 = a3 + n0*m*vp
         a4 = a4 + n1*m*vp
         a5 = a5 + sv
      end do
      if (cur /= 0) call flush_shares(k, cur, lo, hi, shares, a1, a2, a3, a4, a5, mass_left, mass_right, &
                                      momentum_left, momentum_right, stress_volume, seg)
      seg%last_cell(k) = cur
      seg%sums(:, k) = [0.0_dp, 0.0_dp, strain]
      seg%min_volume_ratio(k) = min_j
      seg%max_cell_move(k) = 0
      seg%furthest(k) = 0
      seg%outside(k) = outside
   end subroutine musl_stress_segment
end module mpm_transfer
