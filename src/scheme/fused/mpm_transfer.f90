!> Particle <-> grid transfers with linear shape functions, written as fused passes over the
!> particles: each pass reads and writes every particle once, so a time step costs one or two
!> sweeps through particle memory instead of four or five. Each scheme composes these passes
!> (see mpm_scheme_*). Every pass accumulates the per-step totals the diagnostics and guards need.
!>
!> Notation: a particle in element e with local coordinate xi has N_left = 1 - xi on node e-1 and
!> N_right = xi on node e; dN = -/+ 1/dx. Grid nodal arrays are indexed 0..elements.
!>
!> GIMP (uGIMP, cpGIMP: mpm_shape_gimp) is linear MPM with each particle split in two: its box is cut
!> by a node into a part of fraction r1 in element e and a part r2 = 1 - r1 in element e + 1, and
!> the box average of a hat over a part is the hat at the part's centroid (the hats are linear in an
!> element), t1 and t2 there. So S_I = r1 N_I(t1 in e) + r2 N_I(t2 in e + 1) and dS_I/dx = r1 dN_I(e)
!> + r2 dN_I(e + 1): the GIMP kernels (`gimp`, a named constant like the pass) sum weighted element
!> shares, r (1 - t) m, r t m, ..., r sigma V (accumulate_boxes: one run carries the element's and
!> the next element's sums), and gather as r1 (linear in e at t1) + r2 (linear in e + 1 at t2). The
!> quadratic B-splines split the same way (spline_parts): at coordinate t in the knot span,
!> r1 = 1 - t, r2 = t, t1 = (1 + t)/2, t2 = t/2 give their weights and gradients exactly; the cubic
!> ones split in three about their middle cell (cubic_parts, accumulate_thirds).
!>
!> Speed (see studies/benchmark): each segment kernel walks its particles in blocks of 64. The
!> per-particle update of a block (G2P, stress update, new cell) is one branch-free loop that gfortran
!> vectorises, with or without -march (the per-particle helpers below are elemental and inlined; the
!> cell lookup uses integer arithmetic because a floating-point comparison would keep the loop scalar
!> under gfortran's default trapping-math). The block's totals are summed in 8 lanes. Then the element
!> shares are summed in particle order: particles stay sorted by element, so consecutive particles
!> scatter into the same element and a run of them is summed in registers and written once.
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
   use mpm_kinds, only: dp, i8
   use mpm_grid, only: grid_t, segments_t, share_count, threaded_nodes, node_chunk
   use mpm_particles, only: particles_t, bytes_per_particle, permute
   use mpm_diagnostics, only: pass_totals_t
   use mpm_shape_range, only: infinity_bits
   use mpm_lanes, only: block_size, lanes, largest_move_t, add_lanes, min_lanes, lane_total, track_largest_move, &
                        furthest_particle
   implicit none
   private
   !> The fused passes (fused_pass; what each does: the table in mpm_segment_kernel.inc):
   !>   pass_usf_stress   USF, first half: stress update from the nodal velocities of this step's
   !>                     mapping (d eps = dt sum dN v_I), then stress*volume per element (internal force)
   !>   pass_usf_move     USF, second half: G2P with the solved grid (v_p += dt sum N a_I,
   !>                     x_p += dt sum N v_I), then mass and momentum at the new positions
   !>   pass_usl          USL in one pass: G2P, stress update from the updated nodal velocities, then
   !>                     mass, momentum and stress*volume at the new positions
   !>   pass_musl_remap   MUSL, first pass: G2P, and the new momentum mapped back with the same
   !>                     (start-of-step) shape functions (mass shares unchanged)
   !>   pass_musl_stress  MUSL, second pass: stress update from the remapped nodal velocities, then
   !>                     mass, momentum and stress*volume at the new positions
   integer, parameter, public :: pass_usf_move = 1, pass_usf_stress = 2, pass_usl = 3, pass_musl_remap = 4, &
                                 pass_musl_stress = 5
   public :: pass_totals_t, clear_element_shares, merge_totals
   public :: p2g, fused_pass, fused_box_t, box_cells

   !> The segment kernels are compiled from mpm_segment_arguments.inc, mpm_segment_kernel.inc,
   !> ../../shape/mpm_gimp_box.inc and ../../shape/mpm_bspline_span.inc, whose changes fpm does not
   !> notice (it rebuilds a file when its own text changes: fpm issue #358). Their checksum, here, is
   !> checked by test_kernels, which says the new value after an edit; setting it makes fpm rebuild
   !> this file.
   integer(i8), parameter :: kernel_source_checksum = 1933705291_i8
   public :: kernel_checksum_compiled
   public :: parallel_threshold, segment_particles

   !> Runs with fewer particles are one segment: a pass then costs a few microseconds, less than
   !> waking a second thread is worth.
   integer, parameter :: parallel_threshold = 100000
   !> Target number of particles per segment of a large run: small enough for an even split between
   !> threads, large enough that the per-segment bookkeeping is negligible.
   integer, parameter :: segment_particles = 8192

   !> Which element shares a pass scatters (bit set).
   integer, parameter :: share_mass = 1, share_momentum = 2, share_stress = 4

   !> What each pass does, by pass id (the one place that says it: the segment kernel compiles from
   !> these, fused_pass finishes by them): G2P, stress update, a new cell for each particle, the
   !> element shares it scatters.
   logical, parameter :: pass_moves(5) = [.true., .false., .true., .true., .false.]
   logical, parameter :: pass_stresses(5) = [.false., .true., .true., .false., .true.]
   logical, parameter :: pass_relocates(5) = [.true., .false., .true., .false., .true.]
   integer, parameter :: pass_shares(5) = [share_mass + share_momentum, share_stress, &
                                           share_mass + share_momentum + share_stress, share_momentum, &
                                           share_mass + share_momentum + share_stress]


   !> Runs whose particle data exceed this many bytes (most of this machine's 32 MiB L3 cache) stream
   !> from memory: their kernels then ask for each array's block `prefetch_ahead` particles ahead, and
   !> for the grid values the next blocks read (mpm_prefetch.c), while they sum the current block's
   !> shares, so that memory works during the arithmetic instead of after it. One thread, 1e7
   !> particles: +20-30 %. Smaller runs are in cache, where the hints only cost (USL -5 to -10 % with
   !> 1e4-4e5 particles); 6e5 particles gained 15 %.
   integer(i8), parameter :: prefetch_bytes = 24_i8*1024*1024
   !> Two blocks ahead (about 0.4 us of work at the one-thread rate): one block ahead gained nothing,
   !> three and four blocks ahead less than two.
   integer, parameter :: prefetch_ahead = 2*block_size

   !> The scalars of a segment kernel: the grid's element count, origin and 1/dx, the time step,
   !> Young's modulus, the particles' mass and initial volume, and (GIMP) the initial box half-length
   !> V0/2 and whether the box stretches with J (cpGIMP).
   type :: pass_constants_t
      integer :: elements
      real(dp) :: origin, inv_dx, dt, youngs_modulus, mass, volume0, half_length0
      logical :: stretch
   end type pass_constants_t

   !> The particles' shape on the fused path: the hat (default) or a particle in two parts (`parts`,
   !> see the module's notes): GIMP's box (`stretch`: cpGIMP, l_p = l_p0 J_p) or the quadratic
   !> B-spline's split (`spline`), or in three parts (`cubic`: the cubic B-spline's); and a value per
   !> particle that a pass of such a step keeps for the next (`carry`, for three parts the span
   !> coordinate t in place of r2): MUSL's remap keeps the start-of-step fraction r2 of the box's right part for the
   !> stress pass (the particle has moved since); USF's move pass keeps the new r2 for the next step's
   !> stress pass (which then needs no box), and that pass keeps J at the start of the step in its
   !> place for the move pass (cpGIMP's box).
   type :: fused_box_t
      logical :: parts = .false., stretch = .false., spline = .false., cubic = .false.
      real(dp), allocatable :: carry(:)
   end type fused_box_t

   abstract interface
      !> A segment kernel (see segment_kernel.inc): segment k of one fused pass.
      subroutine segment_kernel(k, seg, x, x0, v, stress, volume_ratio, cell, acceleration, velocity, &
                                strain_increment_of, mass_left, mass_right, momentum_left, momentum_right, &
                                stress_volume, constants, carry)
         import :: dp, segments_t, pass_constants_t
         include 'mpm_segment_arguments.inc'
      end subroutine segment_kernel
   end interface

   interface
      !> Prefetch hint for `bytes` bytes from the address of `first` (see mpm_prefetch.c).
      subroutine mpm_prefetch_lines(first, bytes) bind(c, name='mpm_prefetch_lines')
         use, intrinsic :: iso_c_binding, only: c_int
         type(*), intent(in) :: first
         integer(c_int), value :: bytes
      end subroutine mpm_prefetch_lines
   end interface

   !> The run of particles in one element that a kernel is summing (element 0: none yet).
   type :: run_t
      integer :: cur = 0
      real(dp) :: a(share_count) = 0.0_dp
      !> Particles in parts: the sums of the next element and (three parts) of the one before (see
      !> accumulate_boxes, accumulate_thirds)
      real(dp) :: b(share_count) = 0.0_dp, z(share_count) = 0.0_dp
   end type run_t



contains

   !> kernel_source_checksum as compiled into this module: a function, so that a caller (the test)
   !> gets the value of the object it links, not a copy of the constant taken when the caller itself
   !> was compiled (fpm need not recompile the test when only this module changed).
   integer(i8) function kernel_checksum_compiled()
      kernel_checksum_compiled = kernel_source_checksum
   end function kernel_checksum_compiled

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
      integer :: p, c, cur, shares
      integer(i8) :: elements_bits
      real(dp) :: xi, m, vp, sv, a1, a2, a3, a4, a5
      logical :: sorted
      call clear_element_shares(grid, .true., with_stress)
      call plan_segments(grid, particles%count)
      m = particles%mass
      shares = share_mass + share_momentum
      if (with_stress) shares = shares + share_stress
      elements_bits = transfer(real(grid%elements, dp), 0_i8)
      sorted = .true.
      cur = 0
      a1 = 0; a2 = 0; a3 = 0; a4 = 0; a5 = 0
      do p = 1, particles%count
         call locate_cell(particles%x(p), grid%inv_dx, grid%elements, elements_bits, c, xi)
         if (c == 0) then
            if (totals%outside == 0) totals%outside = p
            cycle
         end if
         particles%cell(p) = c
         if (c /= cur) then
            if (cur /= 0) call add_own_shares(cur, shares, m*(a1 - a2), m*a2, m*(a3 - a4), m*a4, a5, grid%element_mass_left, &
                                              grid%element_mass_right, grid%element_momentum_left, &
                                              grid%element_momentum_right, grid%element_stress_volume)
            if (c < cur) sorted = .false.
            cur = c
            a1 = 0; a2 = 0; a3 = 0; a4 = 0; a5 = 0
         end if
         vp = particles%v(p)
         ! running sums as in accumulate_block: count, xi, v, xi v
         a1 = a1 + 1.0_dp
         a2 = a2 + xi
         a3 = a3 + vp
         a4 = a4 + xi*vp
         if (with_stress) then
            sv = particles%stress(p)*particles%volume_ratio(p)*particles%volume0
            a5 = a5 + sv
         end if
         totals%kinetic_energy = totals%kinetic_energy + 0.5_dp*m*vp**2
         totals%min_volume_ratio = min(totals%min_volume_ratio, particles%volume_ratio(p))
      end do
      if (cur /= 0) call add_own_shares(cur, shares, m*(a1 - a2), m*a2, m*(a3 - a4), m*a4, a5, grid%element_mass_left, &
                                        grid%element_mass_right, grid%element_momentum_left, &
                                        grid%element_momentum_right, grid%element_stress_volume)
      if (.not. sorted .and. grid%segments%count > 1 .and. totals%outside == 0) call sort_by_cell(particles, grid)
   end subroutine p2g

   !> One fused pass over the particles (`pass`, one of the pass_* constants): its segments (on
   !> threads when the run is large, see over_segments), then the halo shares and totals in a fixed
   !> order (finish_pass). The passes that update the stress from the element's velocity difference
   !> get it per element first (strain_increments).
   subroutine fused_pass(pass, particles, grid, dt, youngs_modulus, totals, box)
      integer, intent(in) :: pass
      type(particles_t), intent(inout) :: particles
      type(grid_t), intent(inout) :: grid
      real(dp), intent(in) :: dt, youngs_modulus
      type(pass_totals_t), intent(out) :: totals
      !> the particles' shape (absent: the hat)
      type(fused_box_t), intent(inout), optional :: box
      type(fused_box_t) :: hat
      call prepare_pass(particles, grid)
      ! the passes that update the stress without moving read one strain increment per element
      if (pass_stresses(pass) .and. .not. pass_moves(pass)) call strain_increments(grid, dt)
      if (present(box)) then
         call over_segments(particles, grid, pass, dt, youngs_modulus, box)
         call finish_pass(particles, grid, pass_shares(pass), pass_relocates(pass), totals, box)
      else
         allocate (hat%carry(0))
         call over_segments(particles, grid, pass, dt, youngs_modulus, hat)
         call finish_pass(particles, grid, pass_shares(pass), pass_relocates(pass), totals, hat)
      end if
   end subroutine fused_pass

   !> Each particle's cell for the fused GIMP kernels: the element of its box's left part (see the
   !> module's notes; 0 outside the grid), as a relocating pass leaves it; and in box%carry (when it
   !> has a value per particle) the fraction r2 of its right part, as USF's move pass leaves it.
   subroutine box_cells(particles, grid, box)
      type(particles_t), intent(inout) :: particles
      type(grid_t), intent(in) :: grid
      type(fused_box_t), intent(inout) :: box
      integer :: p, i, flag
      real(dp) :: r1, r2, t1, t2
      do p = 1, particles%count
         if (box%cubic) then ! its middle cell, and its span coordinate (see cubic_parts)
            call bspline3_locate(particles%x(p), grid%origin, grid%inv_dx, grid%elements, i, t1, flag)
            particles%cell(p) = (i + 2)*flag
            if (size(box%carry) == particles%count) box%carry(p) = t1
            cycle
         end if
         call particle_parts(box, particles%x(p), particles%volume0, particles%volume_ratio(p), grid, i, r1, r2, &
                             t1, t2, flag)
         particles%cell(p) = (i + 1)*flag
         if (size(box%carry) == particles%count) box%carry(p) = r2
      end do
   end subroutine box_cells

   !> The two parts of one particle at x (initial volume volume0, J = j) for the shape of `box` (node
   !> i, fractions r1, r2, local coordinates t1, t2, flag: see gimp_box), one particle at a time (the
   !> kernels make the same calls in their loops).
   subroutine particle_parts(box, x, volume0, j, grid, i, r1, r2, t1, t2, flag)
      type(fused_box_t), intent(in) :: box
      real(dp), intent(in) :: x, volume0, j
      type(grid_t), intent(in) :: grid
      integer, intent(out) :: i, flag
      real(dp), intent(out) :: r1, r2, t1, t2
      if (box%spline) then
         call spline_parts((x - grid%origin)*grid%inv_dx, grid%elements, i, r1, r2, t1, t2, flag)
      else
         call gimp_box((x - grid%origin)*grid%inv_dx, box_half_length(0.5_dp*volume0, j, &
                       merge(1.0_dp, 0.0_dp, box%stretch), grid%inv_dx), grid%elements, i, r1, r2, t1, t2, flag)
      end if
   end subroutine particle_parts

   !> The quadratic B-spline of a particle as two parts (see the module's notes): in its knot span
   !> (nodes i, i + 1, i + 2; coordinate t, bspline2_span) the gradient [t - 1, 1 - 2t, t]/dx is
   !> (1 - t) dN(e) + t dN(e + 1), so r1 = 1 - t and r2 = t; the weights [(1-t)^2/2, 1/2 + t - t^2,
   !> t^2/2] are then r1 [1 - t1, t1, 0] + r2 [0, 1 - t2, t2] with t1 = (1 + t)/2, t2 = t/2.
   elemental subroutine spline_parts(s, cells, i, r1, r2, t1, t2, flag)
      real(dp), intent(in) :: s
      integer, intent(in) :: cells
      integer, intent(out) :: i, flag
      real(dp), intent(out) :: r1, r2, t1, t2
      real(dp) :: t
      call bspline2_span(s, cells, i, t, flag)
      r1 = 1.0_dp - t
      r2 = t
      t1 = 0.5_dp*(1.0_dp + t)
      t2 = 0.5_dp*t
   end subroutine spline_parts

   !> The cubic B-spline of a particle as three parts (see the module's notes): at coordinate t in the
   !> middle cell e of its support (nodes e - 2 .. e + 1, bspline3_locate), the gradient
   !> [-(1-t)^2/2, 3t^2/2 - 2t, -3t^2/2 + t + 1/2, t^2/2]/dx is r1 dN(e - 1) + r2 dN(e) + r3 dN(e + 1)
   !> with r = the quadratic B-spline's weights at t, r1 = (1-t)^2/2, r2 = 1/2 + t - t^2, r3 = t^2/2;
   !> the weights [(1-t)^3, 3t^3 - 6t^2 + 4, -3t^3 + 3t^2 + 3t + 1, t^3]/6 are then the three parts'
   !> hats with q = r t_k (the part's fraction times its local coordinate): q1 = (1-t)^2 (2+t)/6,
   !> q2 = (1 + 3t - 2t^3)/6, q3 = t^3/6 (so that N = [r1 - q1, q1 + r2 - q2, q2 + r3 - q3, q3]).
   elemental subroutine cubic_parts(t, r1, r2, r3, q1, q2, q3)
      real(dp), intent(in) :: t
      real(dp), intent(out) :: r1, r2, r3, q1, q2, q3
      real(dp), parameter :: sixth = 1.0_dp/6.0_dp
      real(dp) :: u
      u = 1.0_dp - t
      r1 = 0.5_dp*u*u
      r2 = 0.5_dp + t - t*t
      r3 = 0.5_dp*t*t
      q1 = sixth*u*u*(2.0_dp + t)
      q2 = sixth*(1.0_dp + 3.0_dp*t - 2.0_dp*t*t*t)
      q3 = sixth*t*t*t
   end subroutine cubic_parts

   !> G2P of one cubic B-spline particle in three parts (cubic_parts; nodes e - 2 .. e + 1: a0..a3,
   !> v0..v3): v += dt sum N a_I, x += dt sum N v_I; also its contributions to the totals (see
   !> g2p_particle).
   elemental subroutine g2p_cubic(r1, r2, r3, q1, q2, q3, a0, a1, a2, a3, v0, v1, v2, v3, inv_dx, dt, half_m, x0, x, v, &
                                  displacement, kinetic, move)
      real(dp), intent(in) :: r1, r2, r3, q1, q2, q3, a0, a1, a2, a3, v0, v1, v2, v3, inv_dx, dt, half_m, x0
      real(dp), intent(inout) :: x, v
      real(dp), intent(out) :: displacement, kinetic, move
      real(dp) :: dxp
      v = v + dt*(((r1 - q1)*a0 + q1*a1) + ((r2 - q2)*a1 + q2*a2) + ((r3 - q3)*a2 + q3*a3))
      dxp = dt*(((r1 - q1)*v0 + q1*v1) + ((r2 - q2)*v1 + q2*v2) + ((r3 - q3)*v2 + q3*v3))
      x = x + dxp
      displacement = x - x0
      kinetic = half_m*v*v
      move = abs(dxp)*inv_dx
   end subroutine g2p_cubic

   !> GIMP's box half-length in cells, l = V/2 / dx clamped as mpm_shape_gimp clamps it: V = V0 J
   !> (cpGIMP; j = J) or V0.
   elemental real(dp) function box_half_length(half_length0, j, stretch, inv_dx) result(l)
      real(dp), intent(in) :: half_length0, j, inv_dx
      !> 1 (cpGIMP) or 0: V0 (s J + 1 - s) is V0 J or V0 exactly, and no branch (a merge of a logical
      !> here kept the kernels' loops from vectorising)
      real(dp), intent(in) :: stretch
      l = min(max(half_length0*(stretch*j + (1.0_dp - stretch))*inv_dx, 1.0e-9_dp), 0.5_dp)
   end function box_half_length

   !> Run pass `kind` over every segment: on OpenMP threads when the run has several segments and
   !> is not itself inside a parallel region (a sweep), else in this thread. A branch, not an `if`
   !> clause: an inactive parallel region still costs a team set-up (about a microsecond) per pass,
   !> which dominated small runs.
   subroutine over_segments(particles, grid, kind, dt, youngs_modulus, box)
      type(particles_t), intent(inout) :: particles
      type(grid_t), intent(inout) :: grid
      integer, intent(in) :: kind
      real(dp), intent(in) :: dt, youngs_modulus
      type(fused_box_t), intent(inout) :: box
      integer :: k
      procedure(segment_kernel), pointer :: kernel
      type(pass_constants_t) :: constants
      constants = pass_constants_t(grid%elements, grid%origin, grid%inv_dx, dt, youngs_modulus, particles%mass, &
                                   particles%volume0, 0.5_dp*particles%volume0, box%stretch)
      if (box%cubic) then
         select case (kind)
         case (pass_usf_move)
            kernel => bspline3_usf_move_segment
         case (pass_usf_stress)
            kernel => bspline3_usf_stress_segment
         case (pass_usl)
            kernel => bspline3_usl_segment
         case (pass_musl_remap)
            kernel => bspline3_musl_remap_segment
         case default
            kernel => bspline3_musl_stress_segment
         end select
      else if (box%spline) then
         select case (kind)
         case (pass_usf_move)
            kernel => bspline2_usf_move_segment
         case (pass_usf_stress)
            kernel => bspline2_usf_stress_segment
         case (pass_usl)
            kernel => bspline2_usl_segment
         case (pass_musl_remap)
            kernel => bspline2_musl_remap_segment
         case default
            kernel => bspline2_musl_stress_segment
         end select
      else if (box%parts .and. box%stretch) then
         select case (kind)
         case (pass_usf_move)
            kernel => cpgimp_usf_move_segment
         case (pass_usf_stress)
            kernel => cpgimp_usf_stress_segment
         case (pass_usl)
            kernel => cpgimp_usl_segment
         case (pass_musl_remap)
            kernel => cpgimp_musl_remap_segment
         case default
            kernel => cpgimp_musl_stress_segment
         end select
      else if (box%parts) then
         select case (kind)
         case (pass_usf_move)
            kernel => ugimp_usf_move_segment
         case (pass_usf_stress)
            kernel => ugimp_usf_stress_segment
         case (pass_usl)
            kernel => ugimp_usl_segment
         case (pass_musl_remap)
            kernel => ugimp_musl_remap_segment
         case default
            kernel => ugimp_musl_stress_segment
         end select
      else
         select case (kind)
         case (pass_usf_move)
            kernel => usf_move_segment
         case (pass_usf_stress)
            kernel => usf_stress_segment
         case (pass_usl)
            kernel => usl_segment
         case (pass_musl_remap)
            kernel => musl_remap_segment
         case default
            kernel => musl_stress_segment
         end select
      end if
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
         call kernel(k, grid%segments, particles%x, particles%x0, particles%v, particles%stress, particles%volume_ratio, &
                     particles%cell, grid%acceleration, grid%velocity, grid%element_strain, grid%element_mass_left, &
                     grid%element_mass_right, grid%element_momentum_left, grid%element_momentum_right, &
                     grid%element_stress_volume, constants, box%carry)
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

   !> Strain increment of a linear element from its nodal velocities: d eps = dt sum dN v_I.
   elemental real(dp) function strain_increment(velocity_left, velocity_right, dt, inv_dx) result(dstrain)
      real(dp), intent(in) :: velocity_left, velocity_right, dt, inv_dx
      dstrain = dt*(velocity_right - velocity_left)*inv_dx
   end function strain_increment

   !> grid%element_strain(e) = strain_increment of element e from the nodal velocities (for the passes
   !> that update only the stress). Here, not in mpm_grid, so that the kernels inline the same function.
   subroutine strain_increments(grid, dt)
      type(grid_t), intent(inout) :: grid
      real(dp), intent(in) :: dt
      integer :: k
      if (threaded_nodes(grid)) then
         !$omp parallel do default(shared) private(k) schedule(static)
         do k = 0, (grid%elements - 1)/node_chunk
            call strain_range(1 + k*node_chunk, min(grid%elements, (k + 1)*node_chunk), dt, grid%inv_dx, &
                              grid%velocity, grid%element_strain)
         end do
         !$omp end parallel do
      else
         call strain_range(1, grid%elements, dt, grid%inv_dx, grid%velocity, grid%element_strain)
      end if
   end subroutine strain_increments

   subroutine strain_range(lo, hi, dt, inv_dx, velocity, strain)
      integer, intent(in) :: lo, hi
      real(dp), intent(in) :: dt, inv_dx
      real(dp), intent(in), contiguous :: velocity(0:)
      real(dp), intent(inout), contiguous :: strain(:)
      strain(lo:hi) = strain_increment(velocity(lo - 1:hi - 1), velocity(lo:hi), dt, inv_dx)
   end subroutine strain_range

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
         seg%first_particle = 0  ! no earlier ranges to start the search from
         seg%prefetch = int(count, i8)*bytes_per_particle > prefetch_bytes
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
   !> starts at the first particle whose cell is at least the segment's first element. Searched
   !> outwards from where it was at the last pass (particles move less than an element per step, so
   !> a few probes near the old boundary, in cache), then by bisection: a plain bisection over all
   !> particles cost a cache miss per probe, a serial 1-2 % of a two-thread step with 1e7 particles.
   subroutine find_particle_ranges(seg, cell, count)
      type(segments_t), intent(inout) :: seg
      integer, intent(in), contiguous :: cell(:)
      integer, intent(in) :: count
      integer :: k, lo, hi, mid, step, guess
      logical :: known
      known = seg%first_particle(seg%count + 1) == count + 1
      seg%first_particle(1) = 1
      seg%first_particle(seg%count + 1) = count + 1
      do k = 2, seg%count
         ! the answer lies in [lo, hi]: lo = a particle before it (or the previous range's start),
         ! hi = a particle at or after it (or count + 1)
         lo = seg%first_particle(k - 1)
         hi = count + 1
         if (known) then
            guess = min(max(seg%first_particle(k), lo), hi)
            step = 1
            if (guess <= count .and. cell(min(guess, count)) < seg%first_element(k)) then
               lo = guess + 1  ! boundary is after the guess: gallop up
               do while (lo + step - 1 <= count)
                  if (cell(lo + step - 1) >= seg%first_element(k)) then
                     hi = lo + step - 1
                     exit
                  end if
                  lo = lo + step
                  step = 2*step
               end do
            else
               hi = guess  ! boundary is at or before the guess: gallop down
               do while (hi - step >= lo)
                  if (cell(hi - step) < seg%first_element(k)) then
                     lo = hi - step + 1
                     exit
                  end if
                  hi = hi - step
                  step = 2*step
               end do
            end if
         end if
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
   subroutine finish_pass(particles, grid, shares, moved, totals, box)
      type(particles_t), intent(inout) :: particles
      type(grid_t), intent(inout) :: grid
      integer, intent(in) :: shares
      logical, intent(in) :: moved
      type(pass_totals_t), intent(inout) :: totals
      type(fused_box_t), intent(inout) :: box
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
         if (far) call add_far_movers(particles, grid, shares, box)
         if (moved .and. .not. sorted .and. seg%count > 1 .and. totals%outside == 0) then
            ! (box%carry needs no reordering: only the last pass of a step relocates, and the next
            ! step's first pass writes it afresh)
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
   subroutine add_far_movers(particles, grid, shares, box)
      type(particles_t), intent(inout) :: particles
      type(grid_t), intent(inout) :: grid
      integer, intent(in) :: shares
      type(fused_box_t), intent(in) :: box
      integer :: k, p, c, lo, hi, i, flag
      real(dp) :: xi, m, r1, r2, r3, t1, t2, q1, q2, q3
      m = particles%mass
      associate (seg => grid%segments)
         do k = 1, seg%count
            if (.not. seg%far(k)) cycle
            lo = seg%first_element(k)
            hi = seg%first_element(k + 1) - 1
            do p = seg%first_particle(k), seg%first_particle(k + 1) - 1
               c = particles%cell(p)
               if (box%cubic) then ! the three parts about the middle cell c
                  call bspline3_locate(particles%x(p), grid%origin, grid%inv_dx, grid%elements, i, t1, flag)
                  call cubic_parts(t1, r1, r2, r3, q1, q2, q3)
                  if (c - 1 < lo - 1 .or. c - 1 > hi + 1) call add_part(c - 1, r1, q1)
                  if (c < lo - 1 .or. c > hi + 1) call add_part(c, r2, q2)
                  if (c + 1 < lo - 1 .or. c + 1 > hi + 1) call add_part(c + 1, r3, q3)
               else if (box%parts) then ! the particle's two parts, each where the kernel could not add it
                  call particle_parts(box, particles%x(p), particles%volume0, particles%volume_ratio(p), grid, i, r1, &
                                      r2, t1, t2, flag)
                  if (c < lo - 1 .or. c > hi + 1) call add_part(c, r1, r1*t1)
                  if (c + 1 < lo - 1 .or. c + 1 > hi + 1) call add_part(c + 1, r2, r2*t2)
               else
                  if (c >= lo - 1 .and. c <= hi + 1) cycle
                  xi = particles%x(p)*grid%inv_dx - (c - 1)
                  call add_part(c, 1.0_dp, xi)
               end if
            end do
         end do
      end associate
   contains
      !> The shares of particle p's part of fraction r at local coordinate t = q/r in element c.
      subroutine add_part(c, r, q)
         integer, intent(in) :: c
         real(dp), intent(in) :: r, q
         real(dp) :: a(share_count)
         a(1) = (r - q)*m
         a(2) = q*m
         a(3) = (r - q)*m*particles%v(p)
         a(4) = q*m*particles%v(p)
         a(5) = r*particles%stress(p)*particles%volume_ratio(p)*particles%volume0
         call add_share_set(grid, c, a, shares)
      end subroutine add_part
   end subroutine add_far_movers

   !> Stable counting sort of the particles by cell (rare: only when particles overtake each other
   !> across an element boundary, which the bar never does). Allocates its work arrays here.
   !> `furthest`, when given, follows its particle to the new index.
   subroutine sort_by_cell(particles, grid, furthest)
      type(particles_t), intent(inout) :: particles
      type(grid_t), intent(in) :: grid
      integer, intent(inout), optional :: furthest
      integer, allocatable :: next(:), destination(:)
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
      call permute(particles, destination)
      if (present(furthest)) then
         if (furthest >= 1 .and. furthest <= n) furthest = destination(furthest)
      end if
   end subroutine sort_by_cell

   ! ---- the segment kernels: one segment's particles, its own elements, its halo ----

   !> Add the shares a1..a5 of element `c` (mass left/right, momentum left/right, stress*volume) to its
   !> element arrays (those in `shares`).
   pure subroutine add_own_shares(c, shares, a1, a2, a3, a4, a5, mass_left, mass_right, momentum_left, momentum_right, &
                                  stress_volume)
      integer, value :: c, shares
      real(dp), value :: a1, a2, a3, a4, a5   ! by value, as in flush_shares
      real(dp), intent(inout), contiguous :: mass_left(:), mass_right(:), momentum_left(:), momentum_right(:), stress_volume(:)
      if (iand(shares, share_mass) /= 0) then
         mass_left(c) = mass_left(c) + a1
         mass_right(c) = mass_right(c) + a2
      end if
      if (iand(shares, share_momentum) /= 0) then
         momentum_left(c) = momentum_left(c) + a3
         momentum_right(c) = momentum_right(c) + a4
      end if
      if (iand(shares, share_stress) /= 0) stress_volume(c) = stress_volume(c) + a5
   end subroutine add_own_shares

   !> Add the shares of a run of particles in element `c` (its running sums a1..a5, see
   !> accumulate_block; particle mass m) to the grid (own element) or to the halo (neighbour segment's
   !> element); elements further away mark the segment for add_far_movers.
   pure subroutine flush_shares(k, c, lo, hi, shares, m, a1, a2, a3, a4, a5, mass_left, mass_right, &
                                momentum_left, momentum_right, stress_volume, seg)
      ! by value: the caller keeps its running sums in registers (a dummy passed by reference would
      ! make it store them to memory for every particle)
      integer, value :: k, c, lo, hi, shares
      real(dp), value :: m, a1, a2, a3, a4, a5
      real(dp), intent(inout), contiguous :: mass_left(:), mass_right(:), momentum_left(:), momentum_right(:), stress_volume(:)
      type(segments_t), intent(inout) :: seg
      real(dp) :: s1, s2, s3, s4
      s1 = m*(a1 - a2)
      s2 = m*a2
      s3 = m*(a3 - a4)
      s4 = m*a4
      if (c >= lo .and. c <= hi) then
         call add_own_shares(c, shares, s1, s2, s3, s4, a5, mass_left, mass_right, momentum_left, momentum_right, &
                             stress_volume)
      else if (c == lo - 1) then
         seg%halo_left(:, k) = seg%halo_left(:, k) + [s1, s2, s3, s4, a5]
      else if (c == hi + 1) then
         seg%halo_right(:, k) = seg%halo_right(:, k) + [s1, s2, s3, s4, a5]
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

   !> Prefetch hint for the block of particles starting at p of each array given (none past the last
   !> particle; past the segment's last one it helps the next segment).
   subroutine prefetch_block(p, cell, a1, a2, a3, a4, a5)
      integer, intent(in) :: p
      integer, intent(in), contiguous :: cell(:)
      real(dp), intent(in), contiguous :: a1(:)
      real(dp), intent(in), contiguous, optional :: a2(:), a3(:), a4(:), a5(:)
      if (p + block_size - 1 > size(cell)) return
      call mpm_prefetch_lines(cell(p), storage_size(cell)/8*block_size)
      call mpm_prefetch_lines(a1(p), 8*block_size)
      if (present(a2)) call mpm_prefetch_lines(a2(p), 8*block_size)
      if (present(a3)) call mpm_prefetch_lines(a3(p), 8*block_size)
      if (present(a4)) call mpm_prefetch_lines(a4(p), 8*block_size)
      if (present(a5)) call mpm_prefetch_lines(a5(p), 8*block_size)
   end subroutine prefetch_block

   !> Prefetch hints for the nodal values that the next two blocks (see next_elements) will gather.
   subroutine prefetch_nodes(first_cell, last_cell, acceleration, velocity)
      integer, intent(in) :: first_cell, last_cell
      real(dp), intent(in), contiguous :: acceleration(0:), velocity(0:)
      integer :: e, count
      call next_elements(first_cell, last_cell, ubound(velocity, 1), e, count)
      if (count == 0) return
      ! nodes e-1 .. e+count-1 of those elements
      call mpm_prefetch_lines(acceleration(e - 1), 8*(count + 1))
      call mpm_prefetch_lines(velocity(e - 1), 8*(count + 1))
   end subroutine prefetch_nodes

   !> Prefetch hint for the per-element values that the next two blocks (see next_elements) will read.
   subroutine prefetch_elements(first_cell, last_cell, per_element)
      integer, intent(in) :: first_cell, last_cell
      real(dp), intent(in), contiguous :: per_element(:)
      integer :: e, count
      call next_elements(first_cell, last_cell, size(per_element), e, count)
      if (count > 0) call mpm_prefetch_lines(per_element(e), 8*count)
   end subroutine prefetch_elements

   !> The elements the next two blocks will most likely read, for prefetch hints on the grid arrays:
   !> the current block spans elements first_cell..last_cell; the next two are taken to span as many
   !> each, from last_cell + 1 (particles are sorted by element). count = 0: none (the block is
   !> unsorted or holds a particle outside the grid, or the span runs past the grid).
   pure subroutine next_elements(first_cell, last_cell, elements, first, count)
      integer, intent(in) :: first_cell, last_cell, elements
      integer, intent(out) :: first, count
      first = last_cell + 1
      count = 2*(last_cell - first_cell + 1)
      if (first_cell < 1 .or. count < 1 .or. first + count - 1 > elements) count = 0
   end subroutine next_elements

   ! ---- blocks: the per-particle update of a block vectorised, then its element shares in order ----
   !
   ! Each segment kernel walks its particles in blocks of `block_size`. Phase A updates a block in
   ! one loop with no branch (the compiler vectorises it: gathers of the nodal values, the new cell
   ! found with integer arithmetic, see `locate`), leaving in small buffers what the rest needs. The
   ! totals of the block are then added lane by lane (`lanes` partial sums, also vectorised), and
   ! phase B (`accumulate_block`) sums the element shares in particle order (count, xi, v, xi v per run).
   ! The association of every sum is fixed by the segment and block boundaries, never by threads.

   !> Cell of a particle at x and its local coordinate xi in it, for a grid of `elements` elements;
   !> cell 0 when the particle is outside [0, elements dx] (NaN included). Integer arithmetic only:
   !> the sign bit and the ordering of the bit patterns of non-negative doubles decide the range, so
   !> the caller's loop has no floating-point comparison to branch on (gfortran does not vectorise a
   !> loop that has one unless floating-point traps are declared off). x = L (the free end) is in the
   !> last cell, at xi = 1.
   elemental subroutine locate_cell(x, inv_dx, elements, elements_bits, cell, xi)
      real(dp), intent(in) :: x, inv_dx
      integer, intent(in) :: elements
      integer(i8), intent(in) :: elements_bits  !< transfer(real(elements, dp), 0_i8)
      integer, intent(out) :: cell
      real(dp), intent(out) :: xi
      real(dp) :: s
      integer(i8) :: bits
      s = x*inv_dx
      bits = transfer(s, 0_i8)
      ! 1 - (sign bit of bits | sign bit of (elements_bits - bits)): 1 inside, 0 outside
      cell = min(int(s) + 1, elements)*int(1_i8 - ishft(ior(bits, elements_bits - bits), -63))
      xi = s - (cell - 1)
   end subroutine locate_cell

   !> G2P of one particle in element e with its start-of-step shape functions: v += dt sum N a_I,
   !> x += dt sum N v_I. Also gives the particle's local coordinate xi (before the move) and its
   !> contributions to the totals: displacement x - X, kinetic energy, move in cells.
   elemental subroutine g2p_particle(e, acceleration_left, acceleration_right, velocity_left, velocity_right, &
                                     inv_dx, dt, half_m, x0, x, v, xi, displacement, kinetic, move)
      integer, intent(in) :: e
      real(dp), intent(in) :: acceleration_left, acceleration_right, velocity_left, velocity_right
      real(dp), intent(in) :: inv_dx, dt, half_m, x0
      real(dp), intent(inout) :: x, v
      real(dp), intent(out) :: xi, displacement, kinetic, move
      real(dp) :: dxp
      xi = x*inv_dx - (e - 1)
      v = v + dt*((1.0_dp - xi)*acceleration_left + xi*acceleration_right)
      dxp = dt*((1.0_dp - xi)*velocity_left + xi*velocity_right)
      x = x + dxp
      displacement = x - x0
      kinetic = half_m*v*v
      move = abs(dxp)*inv_dx
   end subroutine g2p_particle

   !> G2P of one GIMP particle whose box has the fraction r1 at t1 in element e and r2 at t2 in element
   !> e + 1 (nodes e - 1, e, e + 1: a0..a2, v0..v2): v += dt sum S a_I, x += dt sum S v_I; also its
   !> contributions to the totals (see g2p_particle).
   elemental subroutine g2p_box(r1, r2, t1, t2, a0, a1, a2, v0, v1, v2, inv_dx, dt, half_m, x0, x, v, displacement, &
                                kinetic, move)
      real(dp), intent(in) :: r1, r2, t1, t2, a0, a1, a2, v0, v1, v2, inv_dx, dt, half_m, x0
      real(dp), intent(inout) :: x, v
      real(dp), intent(out) :: displacement, kinetic, move
      real(dp) :: dxp
      v = v + dt*(r1*((1.0_dp - t1)*a0 + t1*a1) + r2*((1.0_dp - t2)*a1 + t2*a2))
      dxp = dt*(r1*((1.0_dp - t1)*v0 + t1*v1) + r2*((1.0_dp - t2)*v1 + t2*v2))
      x = x + dxp
      displacement = x - x0
      kinetic = half_m*v*v
      move = abs(dxp)*inv_dx
   end subroutine g2p_box

   !> Linear elastic stress update of one particle with strain increment dstrain (see strain_increment):
   !> sigma += E d eps, J *= 1 + d eps. Also gives its strain energy sigma^2 J V0 / 2E
   !> (strain_factor = V0 / 2E) and stress*volume.
   elemental subroutine stress_particle(dstrain, youngs_modulus, strain_factor, volume0, stress, volume_ratio, &
                                        strain_energy, stress_volume)
      real(dp), intent(in) :: dstrain, youngs_modulus, strain_factor, volume0
      real(dp), intent(inout) :: stress, volume_ratio
      real(dp), intent(out) :: strain_energy, stress_volume
      stress = stress + youngs_modulus*dstrain
      volume_ratio = volume_ratio*(1.0_dp + dstrain)
      strain_energy = stress*stress*volume_ratio*strain_factor
      stress_volume = stress*volume_ratio*volume0
   end subroutine stress_particle

   !> The first particle of a block found outside the grid (cell 0), unless one was found before.
   subroutine find_outside(n, b0, cells, outside)
      integer, intent(in) :: n, b0
      integer, intent(in) :: cells(:)
      integer, intent(inout) :: outside
      integer :: i
      if (outside /= 0) return
      ! cells are >= 0: a minimum, which gfortran vectorises (any() became an early-exit scalar loop,
      ! about 3 % of a USL pass)
      if (minval(cells(1:n)) > 0) return
      do i = 1, n
         if (cells(i) == 0) then
            outside = b0 - 1 + i
            return
         end if
      end do
   end subroutine find_outside

   !> Phase B: the element shares of a block, in particle order. A run of particles in one element
   !> is summed in registers and flushed once (flush_shares); `run` carries the open run from one
   !> block to the next. Cells 0 (outside the grid) are skipped; the caller records them.
   !> Running sums of a run: a1 = number of particles (an integer here: four similar floating-point
   !> chains were packed into one vector register by gfortran, with shuffles that made the loop
   !> 30 % slower), a2 = sum xi, a3 = sum v, a4 = sum xi v, a5 = sum
   !> stress*volume, so that each particle costs four additions and one multiply-add (one chain of
   !> dependent additions per sum). With N0 = 1 - xi, N1 = xi and equal particle masses m, the shares
   !> follow at the flush: mass m (a1 - a2), m a2; momentum m (a3 - a4), m a4. This rounds differently from
   !> summing m N v per particle (within a few ulps of the element's momentum), the same way for any
   !> thread count, and made the passes about 6 % faster with 1e7 particles.
   subroutine accumulate_block(k, n, cells, xi, vp, sv, m, lo, hi, shares, run, mass_left, mass_right, &
                               momentum_left, momentum_right, stress_volume, seg)
      integer, intent(in) :: k, n, lo, hi, shares
      integer, intent(in) :: cells(:)
      real(dp), intent(in) :: xi(:), vp(:), sv(:), m
      type(run_t), intent(inout) :: run
      real(dp), intent(inout), contiguous :: mass_left(:), mass_right(:), momentum_left(:), momentum_right(:), &
                                             stress_volume(:)
      type(segments_t), intent(inout) :: seg
      integer :: i, c, cur, na
      real(dp) :: a2, a3, a4, a5
      logical :: kinematic, with_stress
      kinematic = iand(shares, share_mass + share_momentum) /= 0
      with_stress = iand(shares, share_stress) /= 0
      cur = run%cur
      na = int(run%a(1)); a2 = run%a(2); a3 = run%a(3); a4 = run%a(4); a5 = run%a(5)
      do i = 1, n
         c = cells(i)
         if (c /= cur) then
            if (c == 0) cycle
            if (cur >= lo .and. cur <= hi) then
               ! the segment's own element (the common case): the adds of add_own_shares written out,
               ! because calling it here (gfortran then inlined flush_shares as well) made the
               ! kernels 7-9 % slower
               if (kinematic) then
                  if (iand(shares, share_mass) /= 0) then
                     mass_left(cur) = mass_left(cur) + m*(na - a2)
                     mass_right(cur) = mass_right(cur) + m*a2
                  end if
                  if (iand(shares, share_momentum) /= 0) then
                     momentum_left(cur) = momentum_left(cur) + m*(a3 - a4)
                     momentum_right(cur) = momentum_right(cur) + m*a4
                  end if
               end if
               if (with_stress) stress_volume(cur) = stress_volume(cur) + a5
            else if (cur /= 0) then
               call flush_shares(k, cur, lo, hi, shares, m, real(na, dp), a2, a3, a4, a5, mass_left, mass_right, &
                                 momentum_left, momentum_right, stress_volume, seg)
            end if
            if (c < cur) seg%unsorted(k) = .true.
            if (cur == 0) seg%first_cell(k) = c
            cur = c
            na = 0; a2 = 0; a3 = 0; a4 = 0; a5 = 0
         end if
         if (kinematic) then
            na = na + 1
            a2 = a2 + xi(i)
            a3 = a3 + vp(i)
            a4 = a4 + xi(i)*vp(i)
         end if
         if (with_stress) a5 = a5 + sv(i)
      end do
      run%cur = cur
      run%a = [real(na, dp), a2, a3, a4, a5]
   end subroutine accumulate_block

   !> Phase B of the GIMP kernels (accumulate_block for boxes): each box adds its left part to its cell
   !> cells(i) and its right part to the next element. left(i, :) and right(i, :) hold a part's
   !> w, w xi, w v, w xi v and w sigma V (fraction w at local coordinate xi: its mass shares are
   !> w (1 - xi) m and w xi m, momentum the same times v, stress w sigma V; the flush forms them as
   !> accumulate_block's). Particles are sorted by cell, so one run carries two sets of sums: `a` for
   !> the run's element and `b` for the next one, which becomes `a` when the run moves on to it.
   subroutine accumulate_boxes(k, n, cells, left, right, m, lo, hi, shares, run, mass_left, mass_right, &
                               momentum_left, momentum_right, stress_volume, seg)
      integer, intent(in) :: k, n, lo, hi, shares
      integer, intent(in) :: cells(:)
      real(dp), intent(in) :: left(:, :), right(:, :), m
      type(run_t), intent(inout) :: run
      real(dp), intent(inout), contiguous :: mass_left(:), mass_right(:), momentum_left(:), momentum_right(:), &
                                             stress_volume(:)
      type(segments_t), intent(inout) :: seg
      integer :: i, c, cur
      real(dp) :: a1, a2, a3, a4, a5, b1, b2, b3, b4, b5
      logical :: kinematic, with_stress
      kinematic = iand(shares, share_mass + share_momentum) /= 0
      with_stress = iand(shares, share_stress) /= 0
      cur = run%cur
      a1 = run%a(1); a2 = run%a(2); a3 = run%a(3); a4 = run%a(4); a5 = run%a(5)
      b1 = run%b(1); b2 = run%b(2); b3 = run%b(3); b4 = run%b(4); b5 = run%b(5)
      i = 1
      do while (i <= n)
         c = cells(i)
         if (c /= cur) then
            if (c == 0) then
               i = i + 1
               cycle
            end if
            if (cur >= lo .and. cur <= hi) then ! the segment's own element
               call add_own_shares(cur, shares, m*(a1 - a2), m*a2, m*(a3 - a4), m*a4, a5, mass_left, mass_right, &
                                   momentum_left, momentum_right, stress_volume)
            else if (cur /= 0) then
               call flush_shares(k, cur, lo, hi, shares, m, a1, a2, a3, a4, a5, mass_left, mass_right, momentum_left, &
                                 momentum_right, stress_volume, seg)
            end if
            ! the next element's sums go on with the run when it moves there, else they are added now
            if (cur /= 0 .and. c /= cur + 1) call flush_shares(k, cur + 1, lo, hi, shares, m, b1, b2, b3, b4, b5, &
                                                              mass_left, mass_right, momentum_left, momentum_right, &
                                                              stress_volume, seg)
            if (c == cur + 1) then
               a1 = b1; a2 = b2; a3 = b3; a4 = b4; a5 = b5
            else
               a1 = 0; a2 = 0; a3 = 0; a4 = 0; a5 = 0
            end if
            b1 = 0; b2 = 0; b3 = 0; b4 = 0; b5 = 0
            if (c < cur) seg%unsorted(k) = .true.
            if (cur == 0) seg%first_cell(k) = c
            cur = c
         end if
         ! the run of particles in cell cur: sums only (a loop of its own, so that the sums stay in
         ! registers: with the calls above in the same loop, gfortran kept them in memory)
         do while (i <= n)
            if (cells(i) /= cur) exit
            ! (only the sums the pass scatters: the tests are the same for the whole loop)
            if (kinematic) then
               a1 = a1 + left(i, 1)
               a2 = a2 + left(i, 2)
               a3 = a3 + left(i, 3)
               a4 = a4 + left(i, 4)
            end if
            if (with_stress) a5 = a5 + left(i, 5)
            if (right(i, 1) /= 0.0_dp) then ! a box cut by a node (1 in ppc of them: the branch is
               if (kinematic) then ! predicted, and the others skip the adds)
                  b1 = b1 + right(i, 1)
                  b2 = b2 + right(i, 2)
                  b3 = b3 + right(i, 3)
                  b4 = b4 + right(i, 4)
               end if
               if (with_stress) b5 = b5 + right(i, 5)
            end if
            i = i + 1
         end do
      end do
      run%cur = cur
      run%a = [a1, a2, a3, a4, a5]
      run%b = [b1, b2, b3, b4, b5]
   end subroutine accumulate_boxes

   !> Phase B of the three-part kernels (cubic B-splines; accumulate_boxes for three parts): each
   !> particle adds left(i, :) to the element before its cell cells(i), mid(i, :) to its cell and
   !> right(i, :) to the one after (w, w xi, w v, w xi v, w sigma V of each part; here w xi = q). The
   !> run carries the sums of the element before (`z`), its own (`a`) and the next (`b`), shifted by
   !> one when the run moves on by one element.
   subroutine accumulate_thirds(k, n, cells, left, mid, right, m, lo, hi, shares, run, mass_left, mass_right, &
                                momentum_left, momentum_right, stress_volume, seg)
      integer, intent(in) :: k, n, lo, hi, shares
      integer, intent(in) :: cells(:)
      real(dp), intent(in) :: left(:, :), mid(:, :), right(:, :), m
      type(run_t), intent(inout) :: run
      real(dp), intent(inout), contiguous :: mass_left(:), mass_right(:), momentum_left(:), momentum_right(:), &
                                             stress_volume(:)
      type(segments_t), intent(inout) :: seg
      integer :: i, c, cur
      ! the sums as scalars, so that they stay in registers (see accumulate_boxes)
      real(dp) :: z1, z2, z3, z4, z5, a1, a2, a3, a4, a5, b1, b2, b3, b4, b5
      logical :: kinematic, with_stress
      kinematic = iand(shares, share_mass + share_momentum) /= 0
      with_stress = iand(shares, share_stress) /= 0
      cur = run%cur
      z1 = run%z(1); z2 = run%z(2); z3 = run%z(3); z4 = run%z(4); z5 = run%z(5)
      a1 = run%a(1); a2 = run%a(2); a3 = run%a(3); a4 = run%a(4); a5 = run%a(5)
      b1 = run%b(1); b2 = run%b(2); b3 = run%b(3); b4 = run%b(4); b5 = run%b(5)
      i = 1
      do while (i <= n)
         c = cells(i)
         if (c /= cur) then
            if (c == 0) then
               i = i + 1
               cycle
            end if
            if (cur - 1 >= lo .and. cur - 1 <= hi) then ! the element before is complete (own: inline)
               call add_own_shares(cur - 1, shares, m*(z1 - z2), m*z2, m*(z3 - z4), m*z4, z5, mass_left, mass_right, &
                                   momentum_left, momentum_right, stress_volume)
            else if (cur /= 0) then
               call flush_shares(k, cur - 1, lo, hi, shares, m, z1, z2, z3, z4, z5, mass_left, mass_right, &
                                 momentum_left, momentum_right, stress_volume, seg)
            end if
            if (cur /= 0) then ! the others carried on, or added now
               if (c /= cur + 1) call flush_shares(k, cur, lo, hi, shares, m, a1, a2, a3, a4, a5, mass_left, &
                                                   mass_right, momentum_left, momentum_right, stress_volume, seg)
               if (c /= cur + 1 .and. c /= cur + 2) call flush_shares(k, cur + 1, lo, hi, shares, m, b1, b2, b3, b4, b5, &
                                                                      mass_left, mass_right, momentum_left, &
                                                                      momentum_right, stress_volume, seg)
            end if
            if (c == cur + 1) then
               z1 = a1; z2 = a2; z3 = a3; z4 = a4; z5 = a5
               a1 = b1; a2 = b2; a3 = b3; a4 = b4; a5 = b5
            else if (c == cur + 2) then
               z1 = b1; z2 = b2; z3 = b3; z4 = b4; z5 = b5
               a1 = 0; a2 = 0; a3 = 0; a4 = 0; a5 = 0
            else
               z1 = 0; z2 = 0; z3 = 0; z4 = 0; z5 = 0
               a1 = 0; a2 = 0; a3 = 0; a4 = 0; a5 = 0
            end if
            b1 = 0; b2 = 0; b3 = 0; b4 = 0; b5 = 0
            if (c < cur) seg%unsorted(k) = .true.
            if (cur == 0) seg%first_cell(k) = c
            cur = c
         end if
         ! the run of particles in cell cur: sums only (see accumulate_boxes)
         do while (i <= n)
            if (cells(i) /= cur) exit
            if (kinematic) then
               z1 = z1 + left(i, 1); z2 = z2 + left(i, 2); z3 = z3 + left(i, 3); z4 = z4 + left(i, 4)
               a1 = a1 + mid(i, 1); a2 = a2 + mid(i, 2); a3 = a3 + mid(i, 3); a4 = a4 + mid(i, 4)
               b1 = b1 + right(i, 1); b2 = b2 + right(i, 2); b3 = b3 + right(i, 3); b4 = b4 + right(i, 4)
            end if
            if (with_stress) then
               z5 = z5 + left(i, 5)
               a5 = a5 + mid(i, 5)
               b5 = b5 + right(i, 5)
            end if
            i = i + 1
         end do
      end do
      run%cur = cur
      run%z = [z1, z2, z3, z4, z5]
      run%a = [a1, a2, a3, a4, a5]
      run%b = [b1, b2, b3, b4, b5]
   end subroutine accumulate_thirds

   !> Flush the open run and record the segment's totals.
   subroutine close_segment(k, shares, m, run, sums, min_j, max_move, furthest, outside, mass_left, mass_right, &
                            momentum_left, momentum_right, stress_volume, seg)
      integer, intent(in) :: k, shares, furthest, outside
      real(dp), intent(in) :: m
      type(run_t), intent(in) :: run
      real(dp), intent(in) :: sums(3), min_j, max_move
      real(dp), intent(inout), contiguous :: mass_left(:), mass_right(:), momentum_left(:), momentum_right(:), &
                                             stress_volume(:)
      type(segments_t), intent(inout) :: seg
      integer :: lo, hi
      lo = seg%first_element(k)
      hi = seg%first_element(k + 1) - 1
      if (run%cur /= 0) call flush_shares(k, run%cur, lo, hi, shares, m, run%a(1), run%a(2), run%a(3), run%a(4), &
                                          run%a(5), mass_left, mass_right, momentum_left, momentum_right, &
                                          stress_volume, seg)
      seg%last_cell(k) = run%cur
      seg%sums(:, k) = sums
      seg%min_volume_ratio(k) = min_j
      seg%max_cell_move(k) = max_move
      seg%furthest(k) = furthest
      seg%outside(k) = outside
   end subroutine close_segment

   ! The five segment kernels: one source (mpm_segment_kernel.inc), compiled once per pass with the
   ! pass as a named constant (over_segments picks one).

   !> USL: G2P, stress update from the updated nodal velocities, P2G at the new position.
   subroutine usl_segment(k, seg, x, x0, v, stress, volume_ratio, cell, acceleration, velocity, strain_increment_of, &
      mass_left, mass_right, momentum_left, momentum_right, stress_volume, constants, carry)
      integer, parameter :: kernel = pass_usl
      logical, parameter :: parts = .false., stretch_box = .false., spline = .false., three = .false.
      include 'mpm_segment_kernel.inc'
   end subroutine usl_segment

   !> USF second half: G2P, then mass and momentum at the new position.
   subroutine usf_move_segment(k, seg, x, x0, v, stress, volume_ratio, cell, acceleration, velocity, strain_increment_of, &
      mass_left, mass_right, momentum_left, momentum_right, stress_volume, constants, carry)
      integer, parameter :: kernel = pass_usf_move
      logical, parameter :: parts = .false., stretch_box = .false., spline = .false., three = .false.
      include 'mpm_segment_kernel.inc'
   end subroutine usf_move_segment

   !> USF first half: stress update, then stress*volume of the (unmoved) particles per element.
   subroutine usf_stress_segment(k, seg, x, x0, v, stress, volume_ratio, cell, acceleration, velocity, strain_increment_of, &
      mass_left, mass_right, momentum_left, momentum_right, stress_volume, constants, carry)
      integer, parameter :: kernel = pass_usf_stress
      logical, parameter :: parts = .false., stretch_box = .false., spline = .false., three = .false.
      include 'mpm_segment_kernel.inc'
   end subroutine usf_stress_segment

   !> MUSL first pass: G2P, and the new momentum back to the start-of-step nodes.
   subroutine musl_remap_segment(k, seg, x, x0, v, stress, volume_ratio, cell, acceleration, velocity, strain_increment_of, &
      mass_left, mass_right, momentum_left, momentum_right, stress_volume, constants, carry)
      integer, parameter :: kernel = pass_musl_remap
      logical, parameter :: parts = .false., stretch_box = .false., spline = .false., three = .false.
      include 'mpm_segment_kernel.inc'
   end subroutine musl_remap_segment

   !> MUSL second pass: stress update with the remapped nodal velocity of the start-of-step cell,
   !> then mass, momentum and stress*volume at the new position.
   subroutine musl_stress_segment(k, seg, x, x0, v, stress, volume_ratio, cell, acceleration, velocity, strain_increment_of, &
      mass_left, mass_right, momentum_left, momentum_right, stress_volume, constants, carry)
      integer, parameter :: kernel = pass_musl_stress
      logical, parameter :: parts = .false., stretch_box = .false., spline = .false., three = .false.
      include 'mpm_segment_kernel.inc'
   end subroutine musl_stress_segment

   ! The same five passes for GIMP's boxes (`gimp`: see the module's notes): uGIMP's fixed boxes, then
   ! cpGIMP's (`stretch_box`: l = l0 J; a named constant too, so that uGIMP's box and its 1/(2l) are
   ! set once per segment).

   subroutine ugimp_usl_segment(k, seg, x, x0, v, stress, volume_ratio, cell, acceleration, velocity, strain_increment_of, &
      mass_left, mass_right, momentum_left, momentum_right, stress_volume, constants, carry)
      integer, parameter :: kernel = pass_usl
      logical, parameter :: parts = .true., stretch_box = .false., spline = .false., three = .false.
      include 'mpm_segment_kernel.inc'
   end subroutine ugimp_usl_segment

   subroutine ugimp_usf_move_segment(k, seg, x, x0, v, stress, volume_ratio, cell, acceleration, velocity, &
      strain_increment_of, mass_left, mass_right, momentum_left, momentum_right, stress_volume, constants, carry)
      integer, parameter :: kernel = pass_usf_move
      logical, parameter :: parts = .true., stretch_box = .false., spline = .false., three = .false.
      include 'mpm_segment_kernel.inc'
   end subroutine ugimp_usf_move_segment

   subroutine ugimp_usf_stress_segment(k, seg, x, x0, v, stress, volume_ratio, cell, acceleration, velocity, &
      strain_increment_of, mass_left, mass_right, momentum_left, momentum_right, stress_volume, constants, carry)
      integer, parameter :: kernel = pass_usf_stress
      logical, parameter :: parts = .true., stretch_box = .false., spline = .false., three = .false.
      include 'mpm_segment_kernel.inc'
   end subroutine ugimp_usf_stress_segment

   subroutine ugimp_musl_remap_segment(k, seg, x, x0, v, stress, volume_ratio, cell, acceleration, velocity, &
      strain_increment_of, mass_left, mass_right, momentum_left, momentum_right, stress_volume, constants, carry)
      integer, parameter :: kernel = pass_musl_remap
      logical, parameter :: parts = .true., stretch_box = .false., spline = .false., three = .false.
      include 'mpm_segment_kernel.inc'
   end subroutine ugimp_musl_remap_segment

   subroutine ugimp_musl_stress_segment(k, seg, x, x0, v, stress, volume_ratio, cell, acceleration, velocity, &
      strain_increment_of, mass_left, mass_right, momentum_left, momentum_right, stress_volume, constants, carry)
      integer, parameter :: kernel = pass_musl_stress
      logical, parameter :: parts = .true., stretch_box = .false., spline = .false., three = .false.
      include 'mpm_segment_kernel.inc'
   end subroutine ugimp_musl_stress_segment

   subroutine cpgimp_usl_segment(k, seg, x, x0, v, stress, volume_ratio, cell, acceleration, velocity, strain_increment_of, &
      mass_left, mass_right, momentum_left, momentum_right, stress_volume, constants, carry)
      integer, parameter :: kernel = pass_usl
      logical, parameter :: parts = .true., stretch_box = .true., spline = .false., three = .false.
      include 'mpm_segment_kernel.inc'
   end subroutine cpgimp_usl_segment

   subroutine cpgimp_usf_move_segment(k, seg, x, x0, v, stress, volume_ratio, cell, acceleration, velocity, &
      strain_increment_of, mass_left, mass_right, momentum_left, momentum_right, stress_volume, constants, carry)
      integer, parameter :: kernel = pass_usf_move
      logical, parameter :: parts = .true., stretch_box = .true., spline = .false., three = .false.
      include 'mpm_segment_kernel.inc'
   end subroutine cpgimp_usf_move_segment

   subroutine cpgimp_usf_stress_segment(k, seg, x, x0, v, stress, volume_ratio, cell, acceleration, velocity, &
      strain_increment_of, mass_left, mass_right, momentum_left, momentum_right, stress_volume, constants, carry)
      integer, parameter :: kernel = pass_usf_stress
      logical, parameter :: parts = .true., stretch_box = .true., spline = .false., three = .false.
      include 'mpm_segment_kernel.inc'
   end subroutine cpgimp_usf_stress_segment

   subroutine cpgimp_musl_remap_segment(k, seg, x, x0, v, stress, volume_ratio, cell, acceleration, velocity, &
      strain_increment_of, mass_left, mass_right, momentum_left, momentum_right, stress_volume, constants, carry)
      integer, parameter :: kernel = pass_musl_remap
      logical, parameter :: parts = .true., stretch_box = .true., spline = .false., three = .false.
      include 'mpm_segment_kernel.inc'
   end subroutine cpgimp_musl_remap_segment

   subroutine cpgimp_musl_stress_segment(k, seg, x, x0, v, stress, volume_ratio, cell, acceleration, velocity, &
      strain_increment_of, mass_left, mass_right, momentum_left, momentum_right, stress_volume, constants, carry)
      integer, parameter :: kernel = pass_musl_stress
      logical, parameter :: parts = .true., stretch_box = .true., spline = .false., three = .false.
      include 'mpm_segment_kernel.inc'
   end subroutine cpgimp_musl_stress_segment

   ! And for the quadratic B-splines (`spline`: see the module's notes).

   subroutine bspline2_usl_segment(k, seg, x, x0, v, stress, volume_ratio, cell, acceleration, velocity, strain_increment_of, &
      mass_left, mass_right, momentum_left, momentum_right, stress_volume, constants, carry)
      integer, parameter :: kernel = pass_usl
      logical, parameter :: parts = .true., stretch_box = .false., spline = .true., three = .false.
      include 'mpm_segment_kernel.inc'
   end subroutine bspline2_usl_segment

   subroutine bspline2_usf_move_segment(k, seg, x, x0, v, stress, volume_ratio, cell, acceleration, velocity, &
      strain_increment_of, mass_left, mass_right, momentum_left, momentum_right, stress_volume, constants, carry)
      integer, parameter :: kernel = pass_usf_move
      logical, parameter :: parts = .true., stretch_box = .false., spline = .true., three = .false.
      include 'mpm_segment_kernel.inc'
   end subroutine bspline2_usf_move_segment

   subroutine bspline2_usf_stress_segment(k, seg, x, x0, v, stress, volume_ratio, cell, acceleration, velocity, &
      strain_increment_of, mass_left, mass_right, momentum_left, momentum_right, stress_volume, constants, carry)
      integer, parameter :: kernel = pass_usf_stress
      logical, parameter :: parts = .true., stretch_box = .false., spline = .true., three = .false.
      include 'mpm_segment_kernel.inc'
   end subroutine bspline2_usf_stress_segment

   subroutine bspline2_musl_remap_segment(k, seg, x, x0, v, stress, volume_ratio, cell, acceleration, velocity, &
      strain_increment_of, mass_left, mass_right, momentum_left, momentum_right, stress_volume, constants, carry)
      integer, parameter :: kernel = pass_musl_remap
      logical, parameter :: parts = .true., stretch_box = .false., spline = .true., three = .false.
      include 'mpm_segment_kernel.inc'
   end subroutine bspline2_musl_remap_segment

   subroutine bspline2_musl_stress_segment(k, seg, x, x0, v, stress, volume_ratio, cell, acceleration, velocity, &
      strain_increment_of, mass_left, mass_right, momentum_left, momentum_right, stress_volume, constants, carry)
      integer, parameter :: kernel = pass_musl_stress
      logical, parameter :: parts = .true., stretch_box = .false., spline = .true., three = .false.
      include 'mpm_segment_kernel.inc'
   end subroutine bspline2_musl_stress_segment

   ! And for the cubic B-splines (`three`: three parts, see cubic_parts).

   subroutine bspline3_usl_segment(k, seg, x, x0, v, stress, volume_ratio, cell, acceleration, velocity, strain_increment_of, &
      mass_left, mass_right, momentum_left, momentum_right, stress_volume, constants, carry)
      integer, parameter :: kernel = pass_usl
      logical, parameter :: parts = .true., stretch_box = .false., spline = .true., three = .true.
      include 'mpm_segment_kernel.inc'
   end subroutine bspline3_usl_segment

   subroutine bspline3_usf_move_segment(k, seg, x, x0, v, stress, volume_ratio, cell, acceleration, velocity, &
      strain_increment_of, mass_left, mass_right, momentum_left, momentum_right, stress_volume, constants, carry)
      integer, parameter :: kernel = pass_usf_move
      logical, parameter :: parts = .true., stretch_box = .false., spline = .true., three = .true.
      include 'mpm_segment_kernel.inc'
   end subroutine bspline3_usf_move_segment

   subroutine bspline3_usf_stress_segment(k, seg, x, x0, v, stress, volume_ratio, cell, acceleration, velocity, &
      strain_increment_of, mass_left, mass_right, momentum_left, momentum_right, stress_volume, constants, carry)
      integer, parameter :: kernel = pass_usf_stress
      logical, parameter :: parts = .true., stretch_box = .false., spline = .true., three = .true.
      include 'mpm_segment_kernel.inc'
   end subroutine bspline3_usf_stress_segment

   subroutine bspline3_musl_remap_segment(k, seg, x, x0, v, stress, volume_ratio, cell, acceleration, velocity, &
      strain_increment_of, mass_left, mass_right, momentum_left, momentum_right, stress_volume, constants, carry)
      integer, parameter :: kernel = pass_musl_remap
      logical, parameter :: parts = .true., stretch_box = .false., spline = .true., three = .true.
      include 'mpm_segment_kernel.inc'
   end subroutine bspline3_musl_remap_segment

   subroutine bspline3_musl_stress_segment(k, seg, x, x0, v, stress, volume_ratio, cell, acceleration, velocity, &
      strain_increment_of, mass_left, mass_right, momentum_left, momentum_right, stress_volume, constants, carry)
      integer, parameter :: kernel = pass_musl_stress
      logical, parameter :: parts = .true., stretch_box = .false., spline = .true., three = .true.
      include 'mpm_segment_kernel.inc'
   end subroutine bspline3_musl_stress_segment

   include '../../shape/mpm_gimp_box.inc'
   include '../../shape/mpm_bspline_span.inc'
end module mpm_transfer
