!> The blocked particle passes of mpm_transfer against a plain one-particle-at-a-time loop written
!> here from the update formulas (mpm_shape for the cell lookup): new particle state, element
!> shares, totals, the particle that moved furthest and the first particle outside the grid.
!> Nodal velocities and accelerations are random (particles overtake each other and cross
!> elements), one node in the middle moves particles by up to two elements, and the last node moves
!> fast enough to throw particles out of the grid. Sizes:
!> 143 particles (two full blocks of 64 and a remainder; one segment) and 200,000 particles
!> (several segments, shares crossing segment borders into the halos). Also: over several passes
!> whose moves shift the particles across segment borders, every particle is updated once, by the
!> segment that now owns it (each pass starts its range search from the last pass's ranges).
program test_fused_passes
   use mpm_kinds, only: dp
   use mpm_errors, only: error_t
   use mpm_shape_linear, only: locate
   use mpm_grid, only: grid_t, grid_init
   use mpm_particles, only: particles_t, particles_init
   use mpm_segments, only: segments_t
   use mpm_transfer, only: pass_totals_t, p2g, fused_pass, pass_usl, pass_usf_move, pass_usf_stress, pass_musl_remap, &
                           pass_musl_stress, fused_box_t
   use mpm_testing, only: tester_t, tester
   use mpm_lanes, only: smallest_value
   use, intrinsic :: ieee_arithmetic, only: ieee_value, ieee_quiet_nan, ieee_is_nan
   use mpm_strings, only: str
   implicit none
   type(tester_t) :: t
   real(dp), parameter :: length = 3.0_dp, density = 2.0_dp, youngs_modulus = 5.0_dp, dt = 0.01_dp

   t = tester('test_fused_passes')
   if (t%case('usl_pass')) then
      call check_pass('usl', 13, 11)
      call check_pass('usl', 20000, 10)
   end if
   if (t%case('usf_passes')) then
      call check_pass('usf', 13, 11)
      call check_pass('usf', 20000, 10)
   end if
   if (t%case('musl_passes')) then
      call check_musl(13, 11)
      call check_musl(20000, 10)
   end if
   if (t%case('moving_ranges')) call check_moving_ranges()
   if (t%case('move_guard')) call check_move_guard()
   if (t%case('smallest_value')) call check_smallest_value()
   call t%finish()

contains


   subroutine check_pass(scheme, elements, per_element)
      character(len=*), intent(in) :: scheme
      integer, intent(in) :: elements, per_element
      type(particles_t) :: particles
      type(grid_t) :: grid
      type(pass_totals_t) :: totals, stress_totals
      type(segments_t) :: seg
      type(error_t), allocatable :: error
      real(dp), allocatable :: x(:), v(:), stress(:), jac(:), move(:), r(:)
      real(dp), allocatable :: mass_left(:), mass_right(:), momentum_left(:), momentum_right(:), stress_volume(:)
      real(dp) :: dx, xi, n0, n1, dxp, dstrain, m, displacement, kinetic, strain, min_j
      integer :: p, e, c, outside, count
      character(len=:), allocatable :: label

      label = scheme//', '//str(elements*per_element)//' particles: '
      call particles_init(particles, elements, per_element, length/elements, density, error)
      call grid_init(grid, elements, length, particles%mass, error)
      count = particles%count
      dx = grid%dx
      m = particles%mass
      allocate (r(count))
      call random_number(r)
      particles%x = particles%x + (r - 0.5_dp)*0.9_dp*dx/per_element
      call random_number(r)
      particles%v = r - 0.5_dp
      call random_number(r)
      particles%stress = 3*r - 1
      call random_number(r)
      particles%volume_ratio = 0.8_dp + 0.4_dp*r
      call p2g(particles, grid, seg, .true., totals)   ! records the cells (and plans the segments)
      ! random nodal fields: moves up to about 0.4 element; a node in the middle moves its neighbours
      ! up to two elements (the furthest particle is inside the run), the last node throws particles out
      call random_number(grid%velocity)
      grid%velocity = (grid%velocity - 0.5_dp)*0.8_dp*dx/dt
      grid%velocity(elements/2) = 2.0_dp*dx/dt
      grid%velocity(elements) = 1.2_dp*dx/dt
      call random_number(grid%acceleration)
      grid%acceleration = grid%acceleration - 0.5_dp

      ! the expected result, one particle at a time
      x = particles%x
      v = particles%v
      stress = particles%stress
      jac = particles%volume_ratio
      allocate (move(count))
      do p = 1, count
         e = particles%cell(p)
         xi = x(p)*grid%inv_dx - (e - 1)
         n0 = 1 - xi
         n1 = xi
         dstrain = dt*(grid%velocity(e) - grid%velocity(e - 1))*grid%inv_dx
         stress(p) = stress(p) + youngs_modulus*dstrain
         jac(p) = jac(p)*(1 + dstrain)
         v(p) = v(p) + dt*(n0*grid%acceleration(e - 1) + n1*grid%acceleration(e))
         dxp = dt*(n0*grid%velocity(e - 1) + n1*grid%velocity(e))
         x(p) = x(p) + dxp
         move(p) = abs(dxp)*grid%inv_dx
      end do
      allocate (mass_left(elements), mass_right(elements), momentum_left(elements), momentum_right(elements), &
                stress_volume(elements))
      mass_left = 0; mass_right = 0; momentum_left = 0; momentum_right = 0; stress_volume = 0
      outside = 0
      do p = 1, count
         if (scheme == 'usf') then  ! the force comes from the unmoved particles
            stress_volume(particles%cell(p)) = stress_volume(particles%cell(p)) + stress(p)*jac(p)*particles%volume0
         end if
         call locate(x(p), grid%inv_dx, elements, c, xi)
         if (c < 1 .or. c > elements) then
            if (outside == 0) outside = p
            cycle
         end if
         mass_left(c) = mass_left(c) + (1 - xi)*m
         mass_right(c) = mass_right(c) + xi*m
         momentum_left(c) = momentum_left(c) + (1 - xi)*m*v(p)
         momentum_right(c) = momentum_right(c) + xi*m*v(p)
         if (scheme == 'usl') stress_volume(c) = stress_volume(c) + stress(p)*jac(p)*particles%volume0
      end do
      displacement = sum(x - particles%x0)
      kinetic = sum(0.5_dp*m*v**2)
      strain = sum(0.5_dp*stress**2*jac*particles%volume0/youngs_modulus)
      min_j = minval(jac)

      ! the pass(es) under test
      if (scheme == 'usl') then
         call fused_pass(pass_usl, particles, grid, seg, dt, youngs_modulus, totals)
      else
         call fused_pass(pass_usf_stress, particles, grid, seg, dt, youngs_modulus, stress_totals)
         call all_close(label//'stress*volume per element (USF force)', grid%element_stress_volume, &
                        stress_volume, 1.0e-11_dp, 1.0e-12_dp)
         call fused_pass(pass_usf_move, particles, grid, seg, dt, 0.0_dp, totals)
         totals%strain_energy = stress_totals%strain_energy
         totals%min_volume_ratio = stress_totals%min_volume_ratio
      end if

      call t%check(label//'some particles left the grid', outside > 0)
      call t%check(label//'some particles changed element', any(particles%cell /= [((p - 1)/per_element + 1, &
                                                                                    p=1, count)]))
      call t%check(label//'first particle outside the grid', totals%outside == outside, &
                   'got '//str(totals%outside)//', expected '//str(outside))
      call t%check(label//'the furthest particle is not the last', maxloc(move, 1) < count - per_element)
      call t%check(label//'particle that moved furthest', totals%furthest == maxloc(move, 1), &
                   'got '//str(totals%furthest)//', expected '//str(maxloc(move, 1)))
      call t%check_close(label//'largest move', totals%max_cell_move, maxval(move), rtol=1.0e-13_dp)
      call all_close(label//'positions', particles%x, x, 1.0e-14_dp, 1.0e-14_dp)
      call all_close(label//'velocities', particles%v, v, 1.0e-13_dp, 1.0e-14_dp)
      call all_close(label//'stresses', particles%stress, stress, 1.0e-13_dp, 1.0e-13_dp)
      call all_close(label//'volume ratios', particles%volume_ratio, jac, 1.0e-14_dp, 0.0_dp)
      call t%check_close(label//'sum of displacements', totals%displacement, displacement, rtol=1.0e-10_dp, &
                         atol=1.0e-12_dp*count)
      call t%check_close(label//'kinetic energy', totals%kinetic_energy, kinetic, rtol=1.0e-12_dp)
      call t%check_close(label//'strain energy', totals%strain_energy, strain, rtol=1.0e-12_dp)
      call t%check_close(label//'smallest volume ratio', totals%min_volume_ratio, min_j, rtol=1.0e-14_dp)
      ! particles outside the grid add nothing; every other one adds to the element it is now in
      call all_close(label//'mass shares (left)', grid%element_mass_left, mass_left, 1.0e-12_dp, 0.0_dp)
      call all_close(label//'mass shares (right)', grid%element_mass_right, mass_right, 1.0e-12_dp, 0.0_dp)
      call all_close(label//'momentum shares (left)', grid%element_momentum_left, momentum_left, 1.0e-11_dp, 1.0e-12_dp)
      call all_close(label//'momentum shares (right)', grid%element_momentum_right, momentum_right, 1.0e-11_dp, &
                     1.0e-12_dp)
      if (scheme == 'usl') call all_close(label//'stress*volume shares', grid%element_stress_volume, &
                                          stress_volume, 1.0e-11_dp, 1.0e-12_dp)
   end subroutine check_pass

   !> MUSL's two passes against the same one-at-a-time update: the remap pass (G2P, then the new momentum
   !> mapped back with the start-of-step shape functions: element momentum shares at the old cells, mass
   !> shares untouched), then, with new random nodal velocities standing for the remapped ones, the stress
   !> pass (strain from the start-of-step cell) with mass, momentum and stress*volume at the new positions.
   subroutine check_musl(elements, per_element)
      integer, intent(in) :: elements, per_element
      type(particles_t) :: particles
      type(grid_t) :: grid
      type(pass_totals_t) :: totals
      type(segments_t) :: seg
      type(error_t), allocatable :: error
      real(dp), allocatable :: x(:), v(:), stress(:), jac(:), r(:), xi0(:), mass_left0(:), mass_right0(:)
      real(dp), allocatable :: mass_left(:), mass_right(:), momentum_left(:), momentum_right(:), stress_volume(:)
      real(dp) :: xi, m, dstrain
      integer :: p, e, c, count
      integer, allocatable :: cell0(:)
      character(len=:), allocatable :: label
      label = 'musl, '//str(elements*per_element)//' particles: '
      call particles_init(particles, elements, per_element, length/elements, density, error)
      call grid_init(grid, elements, length, particles%mass, error)
      count = particles%count
      m = particles%mass
      allocate (r(count))
      call random_number(r)
      particles%x = particles%x + (r - 0.5_dp)*0.9_dp*grid%dx/per_element
      call random_number(r)
      particles%v = r - 0.5_dp
      call random_number(r)
      particles%stress = 3*r - 1
      call random_number(r)
      particles%volume_ratio = 0.8_dp + 0.4_dp*r
      call p2g(particles, grid, seg, .true., totals)
      mass_left0 = grid%element_mass_left
      mass_right0 = grid%element_mass_right
      call random_number(grid%velocity)
      grid%velocity = (grid%velocity - 0.5_dp)*0.8_dp*grid%dx/dt
      call random_number(grid%acceleration)
      grid%acceleration = grid%acceleration - 0.5_dp
      ! pass 1, one at a time
      x = particles%x
      v = particles%v
      cell0 = particles%cell
      allocate (xi0(count), momentum_left(elements), momentum_right(elements))
      momentum_left = 0
      momentum_right = 0
      do p = 1, count
         e = cell0(p)
         xi0(p) = x(p)*grid%inv_dx - (e - 1)
         v(p) = v(p) + dt*((1 - xi0(p))*grid%acceleration(e - 1) + xi0(p)*grid%acceleration(e))
         x(p) = x(p) + dt*((1 - xi0(p))*grid%velocity(e - 1) + xi0(p)*grid%velocity(e))
         momentum_left(e) = momentum_left(e) + (1 - xi0(p))*m*v(p)
         momentum_right(e) = momentum_right(e) + xi0(p)*m*v(p)
      end do
      call fused_pass(pass_musl_remap, particles, grid, seg, dt, 0.0_dp, totals)
      call all_close(label//'remap: positions', particles%x, x, 1.0e-14_dp, 1.0e-14_dp)
      call all_close(label//'remap: velocities', particles%v, v, 1.0e-13_dp, 1.0e-14_dp)
      call t%check(label//'remap: cells unchanged (start-of-step shape functions)', all(particles%cell == cell0))
      call all_close(label//'remap: momentum shares (left)', grid%element_momentum_left, momentum_left, 1.0e-11_dp, &
                     1.0e-12_dp)
      call all_close(label//'remap: momentum shares (right)', grid%element_momentum_right, momentum_right, 1.0e-11_dp, &
                     1.0e-12_dp)
      call t%check(label//'remap: mass shares untouched', all(grid%element_mass_left == mass_left0) .and. &
                   all(grid%element_mass_right == mass_right0))
      ! pass 2: new nodal velocities stand for the remapped ones
      call random_number(grid%velocity)
      grid%velocity = (grid%velocity - 0.5_dp)*0.8_dp*grid%dx/dt
      stress = particles%stress
      jac = particles%volume_ratio
      allocate (mass_left(elements), mass_right(elements), stress_volume(elements))
      mass_left = 0; mass_right = 0; momentum_left = 0; momentum_right = 0; stress_volume = 0
      do p = 1, count
         e = cell0(p)
         dstrain = dt*(grid%velocity(e) - grid%velocity(e - 1))*grid%inv_dx
         stress(p) = stress(p) + youngs_modulus*dstrain
         jac(p) = jac(p)*(1 + dstrain)
         call locate(x(p), grid%inv_dx, elements, c, xi)
         if (c < 1 .or. c > elements) cycle  ! outside the grid: adds nothing (the guard stops such runs)
         mass_left(c) = mass_left(c) + (1 - xi)*m
         mass_right(c) = mass_right(c) + xi*m
         momentum_left(c) = momentum_left(c) + (1 - xi)*m*v(p)
         momentum_right(c) = momentum_right(c) + xi*m*v(p)
         stress_volume(c) = stress_volume(c) + stress(p)*jac(p)*particles%volume0
      end do
      call fused_pass(pass_musl_stress, particles, grid, seg, dt, youngs_modulus, totals)
      call all_close(label//'stress pass: stresses', particles%stress, stress, 1.0e-13_dp, 1.0e-13_dp)
      call all_close(label//'stress pass: volume ratios', particles%volume_ratio, jac, 1.0e-14_dp, 0.0_dp)
      call all_close(label//'stress pass: mass shares (left)', grid%element_mass_left, mass_left, 1.0e-12_dp, 0.0_dp)
      call all_close(label//'stress pass: mass shares (right)', grid%element_mass_right, mass_right, 1.0e-12_dp, 0.0_dp)
      call all_close(label//'stress pass: momentum shares (left)', grid%element_momentum_left, momentum_left, &
                     1.0e-11_dp, 1.0e-12_dp)
      call all_close(label//'stress pass: stress*volume shares', grid%element_stress_volume, stress_volume, &
                     1.0e-11_dp, 1.0e-12_dp)
      call t%check_close(label//'stress pass: strain energy', totals%strain_energy, &
                         sum(0.5_dp*stress**2*jac*particles%volume0/youngs_modulus), rtol=1.0e-12_dp)
   end subroutine check_musl

   !> Six USL passes over 200,000 particles (about 25 segments) under a smooth nodal velocity that moves
   !> them by up to 0.9 element per pass, right then left: positions against the one-at-a-time update,
   !> and each element's mass against m times the number of particles it now holds.
   subroutine check_moving_ranges()
      integer, parameter :: elements = 20000, per_element = 10
      type(particles_t) :: particles
      type(grid_t) :: grid
      type(pass_totals_t) :: totals
      type(segments_t) :: seg
      type(error_t), allocatable :: error
      real(dp), allocatable :: x(:), held(:)
      integer, allocatable :: start_cells(:)
      logical :: crossed
      real(dp) :: xi, sign
      integer :: pass, p, e, c, i
      character(len=:), allocatable :: label
      call particles_init(particles, elements, per_element, length/elements, density, error)
      call grid_init(grid, elements, length, particles%mass, error)
      call p2g(particles, grid, seg, .true., totals)
      start_cells = particles%cell
      allocate (held(elements))
      do pass = 1, 6
         label = 'moving ranges, pass '//str(pass)//': '
         sign = merge(1.0_dp, -1.0_dp, pass <= 3)
         grid%velocity = [(sign*0.9_dp*grid%dx/dt*sin(acos(-1.0_dp)*i/elements), i=0, elements)]
         grid%acceleration = 0
         x = particles%x
         do p = 1, particles%count
            e = particles%cell(p)
            xi = x(p)*grid%inv_dx - (e - 1)
            x(p) = x(p) + dt*((1 - xi)*grid%velocity(e - 1) + xi*grid%velocity(e))
         end do
         held = 0
         do p = 1, particles%count
            call locate(x(p), grid%inv_dx, elements, c, xi)
            held(c) = held(c) + particles%mass
         end do
         call fused_pass(pass_usl, particles, grid, seg, dt, youngs_modulus, totals)
         call t%check(label//'no particle left the grid', totals%outside == 0)
         if (pass == 3) crossed = any(segment_of(seg, particles%cell) /= segment_of(seg, start_cells))
         call all_close(label//'positions', particles%x, x, 1.0e-14_dp, 1.0e-14_dp)
         call all_close(label//'element masses', grid%element_mass_left + grid%element_mass_right, held, &
                        1.0e-12_dp, 0.0_dp)
      end do
      call t%check('moving ranges: the run has several segments', seg%count > 2)
      call t%check('moving ranges: particles crossed segment borders (after the three moves right, a particle '// &
                   'is in another segment than it started in)', crossed)
   end subroutine check_moving_ranges

   !> The cell-crossing guard's limit on the kernels (fused_box_t's move_guard): a pass names the particle
   !> of the largest move (the one a plain loop finds, maxloc of the moves) where that move is beyond the
   !> limit, and none (0) where it is not; the rest of the pass is the same either way.
   subroutine check_move_guard()
      integer, parameter :: elements = 13, per_element = 11
      type(particles_t) :: particles, start
      type(grid_t) :: grid
      type(pass_totals_t) :: named, unnamed
      type(segments_t) :: seg, start_seg
      type(fused_box_t) :: box
      type(error_t), allocatable :: error
      real(dp), allocatable :: r(:), move(:), x_named(:)
      real(dp) :: xi, largest
      integer :: p, e
      call particles_init(particles, elements, per_element, length/elements, density, error)
      call grid_init(grid, elements, length, particles%mass, error)
      allocate (r(particles%count), move(particles%count))
      call random_number(r)
      particles%x = particles%x + (r - 0.5_dp)*0.9_dp*grid%dx/per_element
      call p2g(particles, grid, seg, .true., named)
      call random_number(grid%velocity)
      grid%velocity = (grid%velocity - 0.5_dp)*0.8_dp*grid%dx/dt
      grid%velocity(elements/2) = 0.9_dp*grid%dx/dt
      grid%acceleration = 0
      do p = 1, particles%count
         e = particles%cell(p)
         xi = particles%x(p)*grid%inv_dx - (e - 1)
         move(p) = abs(dt*((1 - xi)*grid%velocity(e - 1) + xi*grid%velocity(e)))*grid%inv_dx
      end do
      largest = maxval(move)
      start = particles
      start_seg = seg
      allocate (box%carry(0))
      box%move_guard = largest*(1 - 1.0e-9_dp)
      call fused_pass(pass_usl, particles, grid, seg, dt, youngs_modulus, named, box)
      x_named = particles%x
      particles = start
      seg = start_seg
      box%move_guard = largest*(1 + 1.0e-9_dp)
      call fused_pass(pass_usl, particles, grid, seg, dt, youngs_modulus, unnamed, box)
      call t%check('move guard: the largest move is not the first particle''s', maxloc(move, 1) > 1)
      call t%check('move guard below the largest move: that particle named', named%furthest == maxloc(move, 1), &
                   'got '//str(named%furthest)//', expected '//str(maxloc(move, 1)))
      call t%check('move guard above the largest move: none named', unnamed%furthest == 0, &
                   'got '//str(unnamed%furthest))
      call t%check_close('move guard: largest move, named', named%max_cell_move, largest, rtol=1.0e-13_dp)
      call t%check('move guard: the same largest move either way', unnamed%max_cell_move == named%max_cell_move)
      call t%check('move guard: the same positions either way', all(particles%x == x_named))
   end subroutine check_move_guard

   !> The segment of `seg` holding each cell.
   function segment_of(seg, cells) result(segments)
      type(segments_t), intent(in) :: seg
      integer, intent(in) :: cells(:)
      integer :: segments(size(cells)), p
      do p = 1, size(cells)
         segments(p) = count(seg%first_element(1:seg%count) <= cells(p))
      end do
   end function segment_of

   !> Every |actual - expected| <= atol + rtol |expected|; reports the worst entry.
   !> smallest_value against minval: random arrays of 0 to 21 values (every remainder of its four
   !> running minima), with and without NaNs (skipped), all NaN (NaN), empty (huge), +-huge and -0.
   subroutine check_smallest_value()
      real(dp), allocatable :: x(:)
      real(dp) :: nan
      integer :: n, k, wrong
      nan = ieee_value(1.0_dp, ieee_quiet_nan)
      wrong = 0
      do n = 0, 21
         do k = 1, 20
            allocate (x(n))
            call random_number(x)
            x = 2.0_dp*x - 1.0_dp
            if (n > 0 .and. k > 10) x(1 + mod(7*k, n)) = nan
            if (n > 1 .and. k > 15) x(1 + mod(3*k, n)) = -huge(1.0_dp)
            if (.not. (smallest_value(x) == minval(x) .or. (ieee_is_nan(smallest_value(x)) .and. &
                       ieee_is_nan(minval(x))))) wrong = wrong + 1
            deallocate (x)
         end do
      end do
      call t%check('smallest_value = minval on 440 random arrays of 0 to 21 values (NaNs, -huge)', wrong == 0, &
                   str(wrong)//' differ')
      call t%check('smallest_value of all NaN: NaN', ieee_is_nan(smallest_value([nan, nan, nan, nan, nan])))
      call t%check('smallest_value of nothing: huge', smallest_value([real(dp) ::]) == huge(1.0_dp))
      call t%check('smallest_value of huge and NaN: huge', smallest_value([nan, huge(1.0_dp)]) == huge(1.0_dp))
      call t%check('smallest_value finds the minimum in any lane', all([(smallest_value([1.0_dp, 2.0_dp, 3.0_dp, &
                   4.0_dp, 5.0_dp, 6.0_dp] - merge(9.0_dp, 0.0_dp, [(k, k=1, 6)] == n)) == -8.0_dp + n - 1, n=1, 6)]))
   end subroutine check_smallest_value

   subroutine all_close(label, actual, expected, rtol, atol)
      character(len=*), intent(in) :: label
      real(dp), intent(in) :: actual(:), expected(:), rtol, atol
      real(dp) :: excess(size(actual))
      integer :: worst
      excess = abs(actual - expected) - (atol + rtol*abs(expected))
      worst = maxloc(excess, 1)
      call t%check(label, size(actual) == size(expected) .and. all(excess <= 0.0_dp), 'entry '//str(worst)// &
                   ': actual '//str(actual(worst))//', expected '//str(expected(worst)))
   end subroutine all_close
end program test_fused_passes
