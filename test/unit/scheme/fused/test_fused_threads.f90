!> Results do not depend on the number of threads: a run large enough to be split into segments
!> (above mpm_transfer's parallel_threshold) gives bit-for-bit the same particles, grid shares and
!> pass totals with 1 and 2 threads, and the same again when it runs inside a parallel region
!> (as a sweep runs it: the passes then run serially). The grid is large enough for the node loops
!> to run in chunks on threads too (mpm_grid's parallel_nodes), so the comparison with a run inside
!> a parallel region (node loops in one piece) also checks the chunking. Also: particles that overtake each other
!> across an element boundary are sorted back by element, and the grid still conserves mass.
program test_fused_threads
   use omp_lib, only: omp_set_num_threads
   use mpm_kinds, only: dp
   use mpm_errors, only: error_t
   use mpm_grid, only: grid_t, grid_init, assemble_nodes, parallel_nodes
   use mpm_particles, only: particles_t, particles_init
   use mpm_transfer, only: pass_totals_t, parallel_threshold, fused_pass, pass_usl
   use mpm_fused, only: fused_start, fused_step
   use mpm_segments, only: segments_t
   use mpm_schemes, only: scheme_usf, scheme_usl, scheme_musl, scheme_step
   use mpm_testing, only: tester_t, tester
   implicit none
   type(tester_t) :: t
   integer, parameter :: elements = 60000, per_element = 4, steps = 40
   character(len=4), parameter :: schemes(3) = ['usf ', 'usl ', 'musl']
   type(particles_t) :: p1, p2, p3(2)
   type(grid_t) :: g1, g2, g3(2)
   type(pass_totals_t) :: t1, t2, t3(2)
   type(segments_t) :: s1, s2, s3(2)
   integer :: s, i

   t = tester('test_fused_threads')
   ! preconditions of this test (compile-time constants, so not counted as checks): the case must use
   ! the threaded particle passes and node loops, or comparing thread counts proves nothing
   if (elements*per_element < 2*parallel_threshold .or. elements < parallel_nodes) &
      error stop 'test_fused_threads: the case is below the parallel thresholds; enlarge it'
   do s = 1, size(schemes)
      if (.not. t%case(trim(schemes(s)))) cycle
      call omp_set_num_threads(1)
      call run(trim(schemes(s)), p1, g1, s1, t1)
      call t%check(trim(schemes(s))//': no prefetch hints at this size', .not. s1%prefetch)
      ! the second run also with the prefetch hints of large runs: a hint changes no result
      call omp_set_num_threads(2)
      call run(trim(schemes(s)), p2, g2, s2, t2, prefetch=.true.)
      call compare(trim(schemes(s))//' 1 vs 2 threads (and prefetch hints)', p1, g1, t1, p2, g2, t2)
      ! two runs side by side in a parallel region (a sweep): serial passes, same bits
      !$omp parallel do num_threads(2) schedule(static,1)
      do i = 1, 2
         call run(trim(schemes(s)), p3(i), g3(i), s3(i), t3(i))
      end do
      !$omp end parallel do
      do i = 1, 2
         call compare(trim(schemes(s))//' inside a parallel region', p1, g1, t1, p3(i), g3(i), t3(i))
      end do
   end do
   if (t%case('overtaking')) call overtaking()
   if (t%case('large_run_prefetches')) call large_run_prefetches()
   call t%finish()

contains

   subroutine run(scheme, particles, grid, seg, totals, prefetch)
      character(len=*), intent(in) :: scheme
      type(particles_t), intent(out) :: particles
      type(grid_t), intent(out) :: grid
      type(segments_t), intent(out) :: seg
      type(pass_totals_t), intent(out) :: totals
      logical, intent(in), optional :: prefetch
      type(error_t), allocatable :: error
      real(dp), parameter :: length = 25.0_dp, youngs = 200.0e9_dp, density = 7800.0_dp
      real(dp) :: dt
      integer :: n
      call particles_init(particles, elements, per_element, length/elements, density, error)
      call grid_init(grid, elements, length, particles%mass, error, fixed=[0])
      ! a large initial velocity (zero at both ends), so that many particles change element
      particles%v = 200.0_dp*sin(acos(-1.0_dp)*particles%x/length)
      dt = 0.2_dp*(length/elements)/sqrt(youngs/density)
      select case (scheme)
      case ('usf')
         call fused_start(scheme_usf, particles, grid, seg, totals)
      case ('usl')
         call fused_start(scheme_usl, particles, grid, seg, totals)
      case ('musl')
         call fused_start(scheme_musl, particles, grid, seg, totals)
      end select
      if (present(prefetch)) seg%prefetch = prefetch
      do n = 1, steps
         select case (scheme)
         case ('usf')
            call fused_step(scheme_usf, particles, grid, seg, dt, youngs, totals)
         case ('usl')
            call fused_step(scheme_usl, particles, grid, seg, dt, youngs, totals)
         case ('musl')
            call fused_step(scheme_musl, particles, grid, seg, dt, youngs, totals)
         end select
      end do
   end subroutine run

   subroutine compare(label, pa, ga, ta, pb, gb, tb)
      character(len=*), intent(in) :: label
      type(particles_t), intent(in) :: pa, pb
      type(grid_t), intent(in) :: ga, gb
      type(pass_totals_t), intent(in) :: ta, tb
      integer :: j
      call t%check(label//': particles identical', all(pa%x == pb%x) .and. all(pa%v == pb%v) .and. &
                   all(pa%stress == pb%stress) .and. all(pa%volume_ratio == pb%volume_ratio) .and. &
                   all(pa%x0 == pb%x0) .and. all(pa%cell == pb%cell))
      call t%check(label//': element shares identical', &
                   all(ga%element_mass_left == gb%element_mass_left) .and. &
                   all(ga%element_mass_right == gb%element_mass_right) .and. &
                   all(ga%element_momentum_left == gb%element_momentum_left) .and. &
                   all(ga%element_momentum_right == gb%element_momentum_right) .and. &
                   all(ga%element_stress_volume == gb%element_stress_volume) .and. &
                   all(ga%velocity == gb%velocity))
      call t%check(label//': nodal fields identical', all(ga%mass == gb%mass) .and. &
                   all(ga%momentum == gb%momentum) .and. all(ga%force == gb%force) .and. &
                   all(ga%acceleration == gb%acceleration) .and. ga%min_node_mass == gb%min_node_mass)
      call t%check(label//': totals identical', ta%displacement == tb%displacement .and. &
                   ta%kinetic_energy == tb%kinetic_energy .and. ta%strain_energy == tb%strain_energy .and. &
                   ta%min_volume_ratio == tb%min_volume_ratio .and. ta%max_cell_move == tb%max_cell_move .and. &
                   ta%furthest == tb%furthest .and. ta%outside == tb%outside)
      call t%check(label//': no particle left the grid', ta%outside == 0)
      call t%check(label//': some particles changed element', any(pa%cell /= [((j - 1)/per_element + 1, &
                                                                                 j=1, pa%count)]))
   end subroutine compare

   !> A run whose particle data exceed mpm_transfer's prefetch_bytes (24 MiB) uses the hints.
   subroutine large_run_prefetches()
      type(particles_t) :: particles
      type(grid_t) :: grid
      type(pass_totals_t) :: totals
      type(segments_t) :: seg
      type(error_t), allocatable :: error
      integer, parameter :: large = 150000  ! elements; 4 per element: 600000 particles, 26.4 MB
      call particles_init(particles, large, per_element, 25.0_dp/large, 7800.0_dp, error)
      call grid_init(grid, large, 25.0_dp, particles%mass, error, fixed=[0])
      call fused_start(scheme_usl, particles, grid, seg, totals)
      call t%check('600000 particles (26.4 MB): prefetch hints on', seg%prefetch)
   end subroutine large_run_prefetches

   !> Swap two particles across an element boundary: the pass sorts them back by element, with
   !> the same bits on 1 and 2 threads, and mass is conserved.
   subroutine overtaking()
      type(particles_t) :: pa, pb
      type(grid_t) :: ga, gb
      type(pass_totals_t) :: ta, tb
      type(segments_t) :: sa
      integer :: k, threads
      real(dp) :: tmp
      do threads = 1, 2
         call omp_set_num_threads(threads)
         call run('usl', pa, ga, sa, ta)
         call assemble_nodes(ga, .false.)
         call t%check_close('after the run: mass conserved', sum(ga%mass), pa%mass*pa%count, rtol=1.0e-12_dp)
         ! particle k (last of its element) and k+1 (first of the next) exchange places
         k = (elements/2)*per_element
         tmp = pa%x(k)
         pa%x(k) = pa%x(k + 1)
         pa%x(k + 1) = tmp
         ga%velocity = 0
         ga%acceleration = 0
         call fused_pass(pass_usl, pa, ga, sa, 0.0_dp, 200.0e9_dp, ta)
         call t%check('overtaking: particles sorted by element again', all(pa%cell(2:) >= pa%cell(:pa%count - 1)))
         call assemble_nodes(ga, .false.)
         call t%check_close('overtaking: mass conserved', sum(ga%mass), pa%mass*pa%count, rtol=1.0e-12_dp)
         if (threads == 1) then
            pb = pa
            gb = ga
            tb = ta
         end if
      end do
      call compare('overtaking, 1 vs 2 threads', pa, ga, ta, pb, gb, tb)
   end subroutine overtaking
end program test_fused_threads
