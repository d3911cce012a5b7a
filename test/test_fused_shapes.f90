!> The fused kernels of the particles in parts (uGIMP, cpGIMP and quadratic B-splines in two, cubic
!> B-splines in three, with FLIP on the bar: mpm_transfer, mpm_fused) against the generic path, which
!> is their definition:
!> - USF, USL and MUSL, small amplitude and the issue's large-motion case (v0 = 0.01 c, 200 x 4,
!>   k = 0.5: boxes cross nodes and the free end moves into empty cells): same status and steps,
!>   u_cm histories equal to round-off and kinetic energies to 1e-10 (mpm_testing's check_paths_agree);
!> - a run large enough to be cut into segments (their halos carry the particles' right parts): the same
!>   against the generic path, and bit for bit the same history on 1 and 2 threads;
!> - a particle moved several elements away (its segment's "far mover", added after the pass from
!>   both of its parts): mass and momentum are conserved by the mapping (the element shares sum to
!>   the particles' mass and to sum m v), and the particles are sorted again.
program test_fused_shapes
   use omp_lib, only: omp_set_num_threads
   use mpm_kinds, only: dp
   use mpm_errors, only: error_t
   use mpm_config, only: config_t, resolve_config
   use mpm_simulation, only: run_result_t, run_simulation
   use mpm_grid, only: grid_t, grid_init
   use mpm_particles, only: particles_t, particles_init
   use mpm_transfer, only: pass_totals_t, fused_pass, pass_usl, parallel_threshold
   use mpm_fused, only: fused_start, fused_box_t, fused_shape
   use mpm_shape, only: shape_id
   use mpm_schemes, only: scheme_usl
   use mpm_strings, only: str
   use mpm_testing, only: tester_t, check_paths_agree
   implicit none
   type(tester_t) :: t
   character(len=4), parameter :: schemes(3) = ['usf ', 'usl ', 'musl']
   character(len=8), parameter :: shapes(4) = ['ugimp   ', 'cpgimp  ', 'bspline2', 'bspline3']
   integer :: i, j
   t%name = 'test_fused_shapes'
   do j = 1, size(shapes)
      do i = 1, size(schemes)
         call compare(trim(schemes(i)), trim(shapes(j)), 20, 3, 0.3_dp, 0.1_dp, 2.0_dp)
         call compare(trim(schemes(i)), trim(shapes(j)), 200, 4, 0.5_dp, 0.01_dp*sqrt(200.0e9_dp/7800.0_dp), 2.0_dp)
         call compare(trim(schemes(i)), trim(shapes(j)), 30000, 4, 0.5_dp, 50.0_dp, 0.004_dp, threads=.true.)
      end do
      call far_mover(trim(shapes(j)))
   end do
   call t%finish()

contains

   subroutine compare(scheme, shape, elements, ppc, fraction, v0, periods, threads)
      character(len=*), intent(in) :: scheme, shape
      integer, intent(in) :: elements, ppc
      real(dp), intent(in) :: fraction, v0, periods
      logical, intent(in), optional :: threads
      type(run_result_t) :: fused, generic, two
      type(config_t) :: config
      type(error_t), allocatable :: error
      character(len=:), allocatable :: label
      label = scheme//' '//shape//' '//str(elements)//' x '//str(ppc)//' k '//str(fraction)//' v0 '//str(v0)//': '
      config%scheme = scheme
      config%shape = shape
      config%elements = elements
      config%particles_per_element = ppc
      config%dt_fraction = fraction
      config%velocity_amplitude = v0
      config%periods = periods
      call resolve_config(config)
      call omp_set_num_threads(1)
      call run_simulation(config, fused, error, record_history=.true.)
      config%kernels = 'generic'
      call run_simulation(config, generic, error, record_history=.true.)
      call check_paths_agree(t, label, fused, generic, config%length)
      if (present(threads)) then
         call t%check(label//'the run is cut into segments', fused%particles >= parallel_threshold)
         config%kernels = 'auto'
         call omp_set_num_threads(2)
         call run_simulation(config, two, error, record_history=.true.)
         call omp_set_num_threads(1)
         call t%check(label//'1 and 2 threads give the same u_cm and energy histories', &
                      two%steps_done == fused%steps_done .and. all(two%history%ucm == fused%history%ucm) .and. &
                      all(two%history%kinetic_energy == fused%history%kinetic_energy) .and. &
                      all(two%history%strain_energy == fused%history%strain_energy))
      end if
   end subroutine compare

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
      call fused_start(scheme_usl, particles, grid, totals, box, 200.0e9_dp)
      call t%check(label//'the run is cut into segments shorter than the move', grid%segments%count > 2 .and. &
                   maxval(grid%segments%first_element(2:) - grid%segments%first_element(:grid%segments%count)) < 3000)
      ! 3000.9 elements on, past its segment (about 2000 elements) and its halo: its box (dx/8 about the
      ! element's first sub-cell centre, dx/8 from its left node) then straddles a node, so that both
      ! parts are far (the B-spline's parts both have weight anywhere)
      p = elements*ppc/2 + 1
      particles%x(p) = particles%x(p) + 3000.9_dp*length/elements
      grid%velocity = 0.0_dp
      grid%acceleration = 0.0_dp
      call fused_pass(pass_usl, particles, grid, 0.0_dp, 200.0e9_dp, totals, box)
      ! the element shares hold every particle's whole box once (before the fixed end holds its node)
      call t%check_close(label//'mass conserved', sum(grid%element_mass_left) + sum(grid%element_mass_right), &
                         particles%mass*particles%count, rtol=1.0e-12_dp)
      call t%check_close(label//'momentum conserved', sum(grid%element_momentum_left) + &
                         sum(grid%element_momentum_right), particles%mass*sum(particles%v), rtol=1.0e-11_dp)
      call t%check(label//'particles sorted by cell again', all(particles%cell(2:) >= particles%cell(:particles%count - 1)))
   end subroutine far_mover
end program test_fused_shapes
