!> The fused kernels of the particles in parts (uGIMP, cpGIMP and quadratic B-splines in two, cubic
!> B-splines in three, with FLIP on the bar: mpm_transfer, mpm_fused) against the generic path, which
!> is their definition, for every scheme and shape:
!> - USF, USL and MUSL, small amplitude and the issue's large-motion case (v0 = 0.01 c, 200 x 4,
!>   k = 0.5: boxes cross nodes and the free end moves into empty cells): same status and steps,
!>   u_cm histories equal to round-off and kinetic energies to 1e-10 (mpm_testing_runs' check_paths_agree);
!> - the smallest run that is cut into segments (`parallel_threshold` particles; their halos carry the
!>   particles' right parts), 50 steps at v0 = 0.05 c (particles move up to 1.25 dx, across cells and
!>   segments): the same against the generic path, and bit for bit the same history on 1 and 2
!>   threads (120,000 particles for 960 steps: test_fused_long, second tier);
!> - a particle moved several elements away (its segment's "far mover", added after the pass from
!>   both of its parts): mass and momentum are conserved by the mapping (the element shares sum to
!>   the particles' mass and to sum m v), and the particles are sorted again.
program test_fused_shapes
   use mpm_kinds, only: dp
   use mpm_errors, only: error_t
   use mpm_grid, only: grid_t, grid_init
   use mpm_particles, only: particles_t, particles_init
   use mpm_transfer, only: pass_totals_t, fused_pass, pass_usl, parallel_threshold
   use mpm_fused, only: fused_start, fused_box_t, fused_shape
   use mpm_segments, only: segments_t
   use mpm_shape, only: shape_id
   use mpm_schemes, only: scheme_usl
   use mpm_testing, only: tester_t, tester
   use mpm_testing_runs, only: check_fused_run
   implicit none
   type(tester_t) :: t
   character(len=4), parameter :: schemes(3) = ['usf ', 'usl ', 'musl']
   character(len=8), parameter :: shapes(4) = ['ugimp   ', 'cpgimp  ', 'bspline2', 'bspline3']
   real(dp), parameter :: c = sqrt(200.0e9_dp/7800.0_dp)  ! the bar's wave speed
   integer, parameter :: ppc = 4, segmented = (parallel_threshold + ppc - 1)/ppc  ! elements
   integer :: i, j
   t = tester('test_fused_shapes')
   if (t%case('small_amplitude')) then
      do j = 1, size(shapes)
         do i = 1, size(schemes)
            call check_fused_run(t, trim(schemes(i)), trim(shapes(j)), 20, 3, 0.3_dp, 0.1_dp, 2.0_dp)
         end do
      end do
   end if
   if (t%case('large_motion')) then
      do j = 1, size(shapes)
         do i = 1, size(schemes)
            call check_fused_run(t, trim(schemes(i)), trim(shapes(j)), 200, ppc, 0.5_dp, 0.01_dp*c, 2.0_dp)
         end do
      end do
   end if
   if (t%case('segments')) then
      do j = 1, size(shapes)
         do i = 1, size(schemes)
            ! 50 steps (the period is 4 L/c, dt = k L/(elements c)) in which particles move up to 1.25 dx
            call check_fused_run(t, trim(schemes(i)), trim(shapes(j)), segmented, ppc, 0.5_dp, 0.05_dp*c, &
                                 50*0.5_dp/(4.0_dp*segmented), segments=.true.)
         end do
      end do
   end if
   if (t%case('far_mover')) then
      do j = 1, size(shapes)
         call far_mover(trim(shapes(j)))
      end do
   end if
   call t%finish()

contains

   !> A particle of a segmented run moved 3000.9 elements to the right: its two parts land outside its
   !> segment and its halo and are added after the pass (add_far_movers); the mapping conserves mass
   !> and momentum, and the pass sorts the particles by cell again.
   subroutine far_mover(shape)
      character(len=*), intent(in) :: shape
      integer, parameter :: elements = 60000, ppc = 4
      real(dp), parameter :: length = 25.0_dp, density = 7800.0_dp
      type(particles_t) :: particles
      type(grid_t) :: grid
      type(pass_totals_t) :: totals
      type(segments_t) :: seg
      type(fused_box_t) :: box
      type(error_t), allocatable :: error
      integer :: p
      character(len=:), allocatable :: label
      label = shape//' far mover: '
      call particles_init(particles, elements, ppc, length/elements, density, error)
      particles%v = 3.0_dp*sin(particles%x)
      if (shape == 'cpgimp') particles%volume_ratio = 1.0_dp + 0.2_dp*sin(7*particles%x)  ! boxes of many lengths
      box = fused_shape(shape_id(shape))
      call grid_init(grid, elements, length, particles%mass, error, margin=20, fixed=[0], element_shares=.true., ghost=1)
      call fused_start(scheme_usl, particles, grid, seg, totals, box, 200.0e9_dp)
      call t%check(label//'the run is cut into segments shorter than the move', seg%count > 2 .and. &
                   maxval(seg%first_element(2:) - seg%first_element(:seg%count)) < 3000)
      ! 3000.9 elements on, past its segment (about 2000 elements) and its halo: its box (dx/8 about the
      ! element's first sub-cell centre, dx/8 from its left node) then straddles a node, so that both
      ! parts are far (the B-spline's parts both have weight anywhere)
      p = elements*ppc/2 + 1
      particles%x(p) = particles%x(p) + 3000.9_dp*length/elements
      grid%velocity = 0.0_dp
      grid%acceleration = 0.0_dp
      call fused_pass(pass_usl, particles, grid, seg, 0.0_dp, 200.0e9_dp, totals, box)
      ! the element shares hold every particle's whole box once (before the fixed end holds its node)
      call t%check_close(label//'mass conserved', sum(grid%element_mass_left) + sum(grid%element_mass_right), &
                         particles%mass*particles%count, rtol=1.0e-12_dp)
      call t%check_close(label//'momentum conserved', sum(grid%element_momentum_left) + &
                         sum(grid%element_momentum_right), particles%mass*sum(particles%v), rtol=1.0e-11_dp)
      call t%check(label//'particles sorted by cell again', all(particles%cell(2:) >= particles%cell(:particles%count - 1)))
   end subroutine far_mover
end program test_fused_shapes
