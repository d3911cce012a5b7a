!> Benchmark driver for mpm1d (studies/benchmark/run.sh calls it; it prints CSV rows on standard output).
!>   mpm1d_bench throughput SCHEME ELEMENTS PPC STEPS REPEATS THREADS [fused|generic [SHAPE [TRANSFER]]]
!>       time STEPS steps of the scheme's passes (as run_simulation makes them, diagnostics included,
!>       set-up excluded), REPEATS times from the same initial state, on the fused kernels (default)
!>       or the generic path (mpm_schemes; one thread):
!>       scheme,elements,ppc,particles,threads,steps,repeat,seconds,particle_steps_per_s
!>       (seconds: with one thread the process's CPU time, so that a core shared with other work
!>       does not count its waiting; with more threads the wall-clock time)
!>       (with SHAPE given: two more columns, shape,transfer; defaults linear, flip; the fused kernels
!>       take every shape with flip)
!>   mpm1d_bench stream N REPEATS
!>       memory bandwidth with 1 and 2 threads over arrays of N doubles:
!>       kernel,threads,bytes_per_element,repeat,seconds,bytes_per_s
!>       triad  a = b + s c   (STREAM's count: 24 bytes, not counting the write-allocate read of a)
!>       update a = a + s b   (read a, b, write a: 24 bytes really moved; the access pattern of the passes)
!>       particles            the memory traffic of one USL pass with next to no arithmetic: N/4 particles,
!>                            read x, X, v, stress, J, cell and write x, v, stress, J, cell (80 bytes), so
!>                            the rate a pass could reach if only memory limited it (11 streams, not 3)
!>   mpm1d_bench study SCHEME ELEMENTS PPC DT_FRACTION END_TIME REPEATS
!>       a whole run (run_simulation, no history, no file), as a study runs it:
!>       scheme,elements,ppc,dt_fraction,steps,particles,repeat,seconds
!>   mpm1d_bench scenes ELEMENTS PPC STEPS REPEATS
!>       "only what it needs": each scene's whole run (run_simulation, USL, linear, FLIP, dt = 0.2 dx/c,
!>       STEPS steps, one thread, REPEATS times) and the bytes per particle its run holds (run_bytes):
!>       scene,path,particles,steps,bytes_per_particle,repeat,seconds,particle_steps_per_s
!>   mpm1d_bench ratios PARTICLES PPC STEPS REPEATS SCHEME [RUN]
!>       every scene and transfer against the fused bar (the issue-28 table): REPEATS rounds, each the
!>       bar's whole run first, then the bar on the generic path, with PIC, the blend (FLIP fraction 0.95)
!>       and APIC, the column, the composite bar, the manufactured solution, the impact (frictionless and
!>       stuck), the bar with the cures (total-Lagrangian, CPDI, XPIC(2), FMPM(2), ASFLIP(0.99)), each a whole run as a user starts one (run_simulation: set-up included, no history, no
!>       file; linear shapes, dt = 0.2 dx/c, STEPS steps, about PARTICLES particles, PPC per element), then
!>       the bar's kernel (its steps alone, as `throughput` times them); one thread, CPU time:
!>       round,scheme,run,path,particles,steps,bytes_per_particle,seconds,particle_steps_per_s
!>       (with RUN, one of the runs' names, only that run: for instruction counts under valgrind)
!>   mpm1d_bench plastic PARTICLES PPC STEPS REPEATS SCHEME [SHAPE [LAW]]
!>       the elastoplastic bar against the Hencky bar, shape by shape (FLIP): REPEATS rounds, each for every
!>       shape the Hencky bar's whole run, then the same bar elastoplastic (run_simulation as `ratios`
!>       runs it: dt = 0.2 dx/c, STEPS steps, about PARTICLES particles, PPC per element, one thread, CPU
!>       time), with the yield stress a third of the largest stress the elastic bar reaches in the run
!>       (rho c v0 sin(omega T) at the fixed end) and the hardening modulus E/10, so that the bar yields
!>       from a third of the run on; the last column is the fraction of the particles that yielded:
!>       round,scheme,shape,law,path,particles,steps,seconds,particle_steps_per_s,yielded_fraction
!>       (with SHAPE, that shape only; with LAW (hencky or elastoplastic) that law only: for valgrind)
!>   mpm1d_bench implicit PARTICLES PPC STEPS REPEATS [RUN]
!>       an implicit step against an explicit one, at the same dt = 0.5 dx/c and particles (the default
!>       bar, USL on the fused kernels for explicit): REPEATS rounds, each the explicit runs (laws linear
!>       and hencky, 10 STEPS steps) then the implicit ones (linear and hencky, lumped and consistent mass,
!>       STEPS steps), one thread, CPU time: of the whole run (seconds, particle_steps_per_s), the mean Newton
!>       solves per step, and of its time loop alone (the steps without the set-up, paid once a run):
!>       round,run,law,mass,particles,steps,seconds,particle_steps_per_s,solves_per_step,loop_seconds,
!>       loop_particle_steps_per_s
!>       (with RUN, one of explicit_linear, explicit_hencky, implicit_linear_lumped, ..., only that run)
program mpm1d_bench
   use, intrinsic :: iso_fortran_env, only: output_unit, error_unit
   use omp_lib, only: omp_get_wtime, omp_set_num_threads
   use mpm_kinds, only: dp, i8
   use mpm_errors, only: error_t
   use mpm_config, only: config_t, resolve_config, material_of, set_config_values
   use mpm_grid, only: grid_t, grid_init
   use mpm_particles, only: particles_t, per_particle_data, bytes_per_particle
   use mpm_shape, only: shape_cache_t, shape_id, shape_extra_cells, transfer_id, transfer_apic, shape_name, &
                        transfer_name, transfer_flip, shape_support, shape_ugimp, shape_cpgimp, &
                        shape_cpdi, transfer_asflip
   use mpm_transfer, only: pass_totals_t
   use mpm_fused, only: fused_start, fused_step, fused_box_t, fused_shape, fused_choose
   use mpm_segments, only: segments_t
   use mpm_schemes, only: scheme_usf, scheme_usl, scheme_musl, scheme_step, scheme_id
   use mpm_fused_cpdi, only: cpdi_fast
   use mpm_strings, only: str
   use mpm_scene_bar, only: bar_t, bar_init, bar_input_t
   use mpm_scene_impact, only: impact_input_t
   use mpm_simulation, only: run_result_t, run_simulation
   use mpm_scene, only: scene_t
   implicit none
   character(len=32) :: mode

   call get_command_argument(1, mode)
   select case (trim(mode))
   case ('throughput')
      call throughput()
   case ('stream')
      call stream()
   case ('study')
      call study()
   case ('scenes')
      call scenes()
   case ('ratios')
      call ratios()
   case ('plastic')
      call plastic()
   case ('implicit')
      call implicit()
   case default
      call usage('')
   end select

contains

   function arg(i) result(text)
      integer, intent(in) :: i
      character(len=64) :: text
      call get_command_argument(i, text)
   end function arg

   !> Print the usage (after `problem`, when given) and stop with exit status 2.
   subroutine usage(problem)
      character(len=*), intent(in) :: problem
      if (len(problem) > 0) write (error_unit, '(a)') 'mpm1d_bench: '//problem
      write (error_unit, '(a)') 'usage: mpm1d_bench throughput SCHEME ELEMENTS PPC STEPS REPEATS THREADS '// &
         '[fused|generic [SHAPE [TRANSFER]]]', &
         '       mpm1d_bench stream N REPEATS', &
         '       mpm1d_bench study SCHEME ELEMENTS PPC DT_FRACTION END_TIME REPEATS', &
         '       mpm1d_bench scenes ELEMENTS PPC STEPS REPEATS', &
         '       mpm1d_bench ratios PARTICLES PPC STEPS REPEATS SCHEME [RUN]', &
         '       mpm1d_bench plastic PARTICLES PPC STEPS REPEATS SCHEME [SHAPE [LAW]]', &
         '       mpm1d_bench implicit PARTICLES PPC STEPS REPEATS [RUN]', &
         '(studies/benchmark/bench.f90 says what each prints)'
      stop 2, quiet=.true.
   end subroutine usage

   integer function iarg(i)
      integer, intent(in) :: i
      character(len=64) :: text
      integer :: stat
      text = arg(i)
      read (text, *, iostat=stat) iarg
      if (stat /= 0 .or. len_trim(text) == 0) call usage('argument '//achar(48 + i)//' of '//trim(arg(1))// &
                                                         ' is missing or not a whole number')
   end function iarg

   real(dp) function rarg(i)
      integer, intent(in) :: i
      character(len=64) :: text
      integer :: stat
      text = arg(i)
      read (text, *, iostat=stat) rarg
      if (stat /= 0 .or. len_trim(text) == 0) call usage('argument '//achar(48 + i)//' of '//trim(arg(1))// &
                                                         ' is missing or not a number')
   end function rarg

   subroutine throughput()
      type(config_t) :: config
      type(bar_t) :: bar
      type(grid_t) :: grid
      type(particles_t) :: particles
      type(pass_totals_t) :: totals
      type(segments_t) :: seg
      type(error_t), allocatable :: error
      type(shape_cache_t) :: cache
      type(fused_box_t) :: box
      integer :: steps, repeats, threads, r, n, scheme, extra
      real(dp) :: start, seconds, ucm, worst, total_mass
      logical :: generic
      character(len=:), allocatable :: columns
      config%scheme = arg(2)
      config%elements = iarg(3)
      config%particles_per_element = iarg(4)
      steps = iarg(5)
      repeats = iarg(6)
      threads = iarg(7)
      call resolve_config(config)
      call omp_set_num_threads(threads)
      bar = bar_of(config)
      generic = trim(arg(8)) == 'generic'
      columns = ''
      if (len_trim(arg(9)) > 0) then
         cache%kind = shape_id(arg(9))
         if (len_trim(arg(10)) > 0) cache%transfer = transfer_id(arg(10))
         if (cache%kind == 0 .or. cache%transfer == 0) error stop 'unknown shape or transfer'
         if (.not. generic .and. cache%transfer /= transfer_flip) error stop 'the fused kernels take flip only'
         columns = ','//shape_name(cache%kind)//','//transfer_name(cache%transfer)
      end if
      box = fused_shape(cache%kind)
      extra = shape_extra_cells(cache%kind)
      select case (trim(config%scheme))
      case ('usf')
         scheme = scheme_usf
      case ('usl')
         scheme = scheme_usl
      case default
         scheme = scheme_musl
      end select
      do r = 1, repeats
         call bar%place_particles(config, particles, error)
         if (allocated(error)) error stop 'out of memory'
         if (generic) call per_particle_data(particles, error)
         if (cache%transfer == transfer_apic) then
            allocate (particles%velocity_gradient(particles%count))
            particles%velocity_gradient = 0
         end if
         call grid_init(grid, config%elements, config%length, particles%mass, error, &
                        margin=bar%margin_cells(config%dx, -1) + extra, fixed=bar%fixed_nodes(), &
                        element_shares=.not. generic, ghost=extra)
         if (generic) then
            total_mass = sum(particles%mass_of)
         else
            call fused_start(scheme, particles, grid, seg, totals, box, config%youngs_modulus)
         end if
         worst = 0
         start = clock(threads)
         do n = 1, steps
            ! the step and the per-step diagnostics run_simulation makes
            if (generic) then
               call scheme_step(scheme, bar, cache, particles, grid, config%dt, config%youngs_modulus, &
                                (n - 1)*config%dt, totals)
               ucm = totals%displacement/total_mass
            else
               call fused_step(scheme, particles, grid, seg, config%dt, config%youngs_modulus, totals, box)
               ucm = totals%displacement/particles%count
            end if
            worst = max(worst, abs(ucm - bar%ucm_exact(n*config%dt)))
         end do
         seconds = clock(threads) - start
         if (totals%outside /= 0 .or. totals%max_cell_move > 1) error stop 'benchmark run left its guards'
         write (output_unit, '(a,",",i0,",",i0,",",i0,",",i0,",",i0,",",i0,",",es12.5,",",es12.5,a)') &
            trim(config%scheme), config%elements, config%particles_per_element, particles%count, threads, steps, r, &
            seconds, real(particles%count, dp)*steps/seconds, columns
         flush (output_unit)
      end do
   end subroutine throughput

   subroutine stream()
      integer(i8) :: n, np, i
      integer :: repeats, r, threads, shift
      real(dp), allocatable :: a(:), b(:), c(:)
      real(dp), allocatable :: x(:), x0(:), v(:), stress(:), volume_ratio(:)
      integer, allocatable :: cell(:)
      real(dp) :: start, seconds, s, h
      n = int(iarg(2), i8)
      repeats = iarg(3)
      np = n/4
      allocate (a(n), b(n), c(n), x(np), x0(np), v(np), stress(np), volume_ratio(np), cell(np))
      call omp_set_num_threads(2)
      !$omp parallel do schedule(static)
      do i = 1, n
         a(i) = 1.0_dp
         b(i) = 2.0_dp
         c(i) = 0.5_dp
      end do
      !$omp parallel do schedule(static)
      do i = 1, np
         x(i) = 1.0_dp
         x0(i) = 1.0_dp
         v(i) = 0.0_dp
         stress(i) = 0.0_dp
         volume_ratio(i) = 1.0_dp
         cell(i) = 1
      end do
      s = 1.0e-3_dp
      h = 1.0e-9_dp
      shift = 0
      if (repeats < 0) shift = 1  ! not known at compile time: the cell store stays
      do threads = 1, 2
         call omp_set_num_threads(threads)
         do r = 1, repeats
            start = omp_get_wtime()
            !$omp parallel do schedule(static)
            do i = 1, n
               a(i) = b(i) + s*c(i)
            end do
            seconds = omp_get_wtime() - start
            call write_bandwidth('triad', threads, 24, r, seconds, n)
            start = omp_get_wtime()
            !$omp parallel do schedule(static)
            do i = 1, n
               a(i) = a(i) + s*b(i)
            end do
            seconds = omp_get_wtime() - start
            call write_bandwidth('update', threads, 24, r, seconds, n)
            ! the traffic of a USL pass over np particles (see the header)
            start = omp_get_wtime()
            !$omp parallel do schedule(static)
            do i = 1, np
               x(i) = x(i) + h*v(i)
               v(i) = v(i) + h*stress(i)
               stress(i) = stress(i) + h*(x(i) - x0(i))
               volume_ratio(i) = volume_ratio(i)*(1.0_dp + h*v(i))
               cell(i) = cell(i) + shift
            end do
            seconds = omp_get_wtime() - start
            call write_bandwidth('particles', threads, 80, r, seconds, np)
         end do
      end do
      if (a(n) < 0 .or. x(np) < 0 .or. cell(np) < 0) write (output_unit, *) a(1), x(1), cell(1) ! keep the loops
   end subroutine stream

   !> One CSV row of `stream`: kernel,threads,bytes_per_element,repeat,seconds,bytes_per_s.
   subroutine write_bandwidth(kernel, threads, bytes, repeat, seconds, n)
      character(len=*), intent(in) :: kernel
      integer, intent(in) :: threads, bytes, repeat
      real(dp), intent(in) :: seconds
      integer(i8), intent(in) :: n
      write (output_unit, '(a,",",i0,",",i0,",",i0,",",es12.5,",",es12.5)') kernel, threads, bytes, repeat, &
         seconds, real(bytes, dp)*n/seconds
   end subroutine write_bandwidth

   subroutine study()
      type(config_t) :: config
      type(run_result_t) :: result
      type(error_t), allocatable :: error
      integer :: repeats, r
      config%scheme = arg(2)
      config%elements = iarg(3)
      config%particles_per_element = iarg(4)
      config%dt_fraction = rarg(5)
      config%end_time = rarg(6)
      repeats = iarg(7)
      config%history = .false.
      call resolve_config(config)
      call omp_set_num_threads(1)
      do r = 1, repeats
         call run_simulation(config, result, error, record_history=.false.)
         if (allocated(error)) error stop 'run failed'
         write (output_unit, '(a,",",i0,",",i0,",",f0.4,",",i0,",",i0,",",i0,",",es12.5)') trim(config%scheme), &
            config%elements, config%particles_per_element, config%dt_fraction, result%steps_done, result%particles, &
            r, result%run_time
         flush (output_unit)
      end do
   end subroutine study

   !> Each scene as the scenes study runs it, at one size: bytes per particle and particle-steps/s.
   subroutine scenes()
      type(config_t) :: config
      integer :: elements, ppc, steps, repeats, k, r
      character(len=32), parameter :: kinds(7) = [character(len=32) :: 'bar', 'bar_generic', 'column', 'manufactured', &
                                                  'composite_bar', 'impact_frictionless', 'impact_none']
      type(run_result_t) :: result
      real(dp) :: seconds
      elements = iarg(2)
      ppc = iarg(3)
      steps = iarg(4)
      repeats = iarg(5)
      call omp_set_num_threads(1)
      do k = 1, size(kinds)
         config = run_config(kinds(k), elements, ppc, steps, 'usl')
         do r = 1, repeats
            call timed_run(config, result, seconds)
            write (output_unit, '(a,",",a,",",i0,",",i0,",",f0.2,",",i0,",",es12.5,",",es12.5)') &
               scene_name(config), trim(merge('fused  ', 'generic', result%fused)), result%particles, result%steps_done, &
               run_bytes(config), r, seconds, real(result%particles, dp)*result%steps_done/seconds
            flush (output_unit)
         end do
      end do
   end subroutine scenes

   !> Every scene and transfer against the fused bar, paired in rounds (see the program's header).
   subroutine ratios()
      character(len=32), parameter :: kinds(15) = [character(len=32) :: 'bar', 'bar_generic', 'bar_pic', 'bar_blend', &
                                                   'bar_apic', 'column', 'composite_bar', 'manufactured', &
                                                   'impact_frictionless', 'impact_none', 'bar_total', 'bar_cpdi', &
                                                   'bar_xpic2', 'bar_fmpm2', 'bar_asflip']
      type(config_t) :: configs(size(kinds))
      type(run_result_t) :: result
      integer :: particles, ppc, steps, repeats, k, r
      real(dp) :: seconds, bytes(size(kinds))
      character(len=:), allocatable :: scheme
      call run_arguments(particles, ppc, steps, repeats, scheme)
      do k = 1, size(kinds)
         configs(k) = run_config(kinds(k), max(1, particles/ppc), ppc, steps, scheme)
         bytes(k) = run_bytes(configs(k))
      end do
      do r = 1, repeats
         do k = 1, size(kinds)
            if (len_trim(arg(7)) > 0 .and. trim(arg(7)) /= trim(kinds(k))) cycle
            call timed_run(configs(k), result, seconds)
            call ratio_row(r, scheme, trim(kinds(k)), trim(merge('fused  ', 'generic', result%fused)), result%particles, &
                           result%steps_done, bytes(k), seconds)
         end do
         if (len_trim(arg(7)) == 0 .or. trim(arg(7)) == 'bar_kernel') call kernel_row(r, scheme, configs(1))
      end do
   end subroutine ratios

   !> The elastoplastic bar against the Hencky bar, shape by shape (see the program's header).
   subroutine plastic()
      character(len=8), parameter :: shapes(5) = [character(len=8) :: 'linear', 'ugimp', 'cpgimp', 'bspline2', &
                                                   'bspline3']
      character(len=16), parameter :: laws(2) = [character(len=16) :: 'hencky', 'elastoplastic']
      type(config_t) :: config
      type(run_result_t) :: result
      integer :: particles, ppc, steps, repeats, r, k, l
      real(dp) :: seconds, reached
      character(len=128) :: line(1)
      character(len=:), allocatable :: scheme
      call run_arguments(particles, ppc, steps, repeats, scheme)
      do r = 1, repeats
         do k = 1, size(shapes)
            if (len_trim(arg(7)) > 0 .and. trim(arg(7)) /= trim(shapes(k))) cycle
            do l = 1, size(laws)
               if (len_trim(arg(8)) > 0 .and. trim(arg(8)) /= trim(laws(l))) cycle
               config = run_config('bar', max(1, particles/ppc), ppc, steps, scheme)
               config%shape = shapes(k)
               config%law = laws(l)
               ! the largest stress of the elastic bar by the end of the run: rho c v0 sin(omega T) at x = 0
               select type (bar => config%scene)
               type is (bar_input_t)
                  reached = bar%density*config%wave_speed*bar%velocity_amplitude* &
                            sin(2*acos(-1.0_dp)*config%end_time/config%period)
               end select
               line(1) = 'material.yield_stress='//str(reached/3)
               call set(config, line)
               line(1) = 'material.hardening_modulus='//str(config%youngs_modulus/10)
               call set(config, line)
               call resolve_config(config)
               call timed_run(config, result, seconds)
               write (output_unit, '(i0,",",a,",",a,",",a,",",a,",",i0,",",i0,",",es12.5,",",es12.5,",",f0.4)') &
                  r, scheme, trim(shapes(k)), trim(laws(l)), trim(merge('fused  ', 'generic', result%fused)), &
                  result%particles, result%steps_done, seconds, real(result%particles, dp)*result%steps_done/seconds, &
                  report_value(result, 'yielded_fraction')
               flush (output_unit)
            end do
         end do
      end do
   end subroutine plastic

   !> An implicit step against an explicit one (see the program's header).
   subroutine implicit()
      character(len=32), parameter :: runs(6) = [character(len=32) :: 'explicit_linear', 'explicit_hencky', &
                                                 'implicit_linear_lumped', 'implicit_hencky_lumped', &
                                                 'implicit_linear_consistent', 'implicit_hencky_consistent']
      type(config_t) :: config
      type(run_result_t) :: result
      integer :: particles, ppc, steps, repeats, r, k, n
      real(dp) :: seconds
      character(len=16) :: law, mass
      particles = iarg(2)
      ppc = iarg(3)
      steps = iarg(4)
      repeats = iarg(5)
      call omp_set_num_threads(1)
      do r = 1, repeats
         do k = 1, size(runs)
            if (len_trim(arg(6)) > 0 .and. trim(arg(6)) /= trim(runs(k))) cycle
            law = 'hencky'
            if (index(runs(k), 'linear') > 0) law = 'linear'
            mass = '-'
            n = 10*steps
            config = run_config('bar', max(1, particles/ppc), ppc, n, 'usl')
            if (runs(k)(1:8) == 'implicit') then
               mass = 'lumped'
               if (index(runs(k), 'consistent') > 0) mass = 'consistent'
               config%integrator = 'implicit'
               config%mass = mass
               n = steps
            end if
            config%law = law
            config%dt_fraction = 0.5_dp
            call resolve_config(config)
            config%end_time = n*config%dt
            call resolve_config(config)
            call timed_run(config, result, seconds)
            write (output_unit, '(i0,",",a,",",a,",",a,",",i0,",",i0,",",es12.5,",",es12.5,",",f0.3,",",es12.5,",",es12.5)') &
               r, trim(runs(k)), trim(law), trim(mass), result%particles, result%steps_done, seconds, &
               real(result%particles, dp)*result%steps_done/seconds, report_value(result, 'newton_iterations'), &
               result%loop_cpu_time, real(result%particles, dp)*result%steps_done/result%loop_cpu_time
            flush (output_unit)
         end do
      end do
   end subroutine implicit

   !> The arguments PARTICLES PPC STEPS REPEATS SCHEME of `ratios` and `plastic`; one thread.
   subroutine run_arguments(particles, ppc, steps, repeats, scheme)
      integer, intent(out) :: particles, ppc, steps, repeats
      character(len=:), allocatable, intent(out) :: scheme
      particles = iarg(2)
      ppc = iarg(3)
      steps = iarg(4)
      repeats = iarg(5)
      scheme = trim(arg(6))
      if (scheme /= 'usf' .and. scheme /= 'usl' .and. scheme /= 'musl') call usage('SCHEME is usf, usl or musl')
      call omp_set_num_threads(1)
   end subroutine run_arguments

   !> The value of report `name` of a run (0 when it has none).
   real(dp) function report_value(result, name) result(value)
      type(run_result_t), intent(in) :: result
      character(len=*), intent(in) :: name
      integer :: k
      value = 0
      do k = 1, size(result%report_names)
         if (trim(result%report_names(k)) == name) value = result%report_values(k)
      end do
   end function report_value

   !> A row of `ratios`.
   subroutine ratio_row(round, scheme, run, path, count, done, per_particle, time)
      integer, intent(in) :: round, count, done
      character(len=*), intent(in) :: scheme, run, path
      real(dp), intent(in) :: per_particle, time
      write (output_unit, '(i0,",",a,",",a,",",a,",",i0,",",i0,",",f0.2,",",es12.5,",",es12.5)') round, scheme, run, &
         path, count, done, per_particle, time, real(count, dp)*done/time
      flush (output_unit)
   end subroutine ratio_row
   !> The bar's steps alone (fused kernels, diagnostics as run_simulation makes them; no set-up).
   subroutine kernel_row(round, scheme, config)
      integer, intent(in) :: round
      character(len=*), intent(in) :: scheme
      type(config_t), intent(in) :: config
      type(bar_t) :: bar
      type(grid_t) :: grid
      type(particles_t) :: particles
      type(pass_totals_t) :: totals
      type(segments_t) :: seg
      type(fused_box_t) :: box
      type(error_t), allocatable :: error
      real(dp) :: start, worst
      integer :: n, id
      bar = bar_of(config)
      call bar%place_particles(config, particles, error)
      if (allocated(error)) error stop 'out of memory'
      call grid_init(grid, config%elements, config%length, particles%mass, error, margin=bar%margin_cells(config%dx, -1), &
                     fixed=bar%fixed_nodes())
      id = merge(scheme_usf, merge(scheme_usl, scheme_musl, scheme == 'usl'), scheme == 'usf')
      box = fused_shape(shape_id('linear'))
      call fused_start(id, particles, grid, seg, totals, box, config%youngs_modulus)
      worst = 0
      start = clock(1)
      do n = 1, config%steps
         call fused_step(id, particles, grid, seg, config%dt, config%youngs_modulus, totals, box)
         worst = max(worst, abs(totals%displacement/particles%count - bar%ucm_exact(n*config%dt)))
      end do
      call ratio_row(round, scheme, 'bar_kernel', 'fused', particles%count, config%steps, &
                     real(bytes_per_particle, dp), clock(1) - start)
      if (worst < 0) write (output_unit, *) worst  ! (keeps the error evaluation)
   end subroutine kernel_row

   !> The configuration of one run of `ratios` and `scenes`: `kind` (bar, bar_generic, bar_pic, bar_blend,
   !> bar_apic, column, manufactured, composite_bar, impact_frictionless, impact_none, bar_total, bar_cpdi, bar_xpic2,
   !> bar_fmpm2, bar_asflip) with `elements` elements
   !> (the impact: its two bars of length 1 together), ppc particles per element, dt = 0.2 dx/c, `steps` steps.
   function run_config(kind, elements, ppc, steps, scheme) result(config)
      character(len=*), intent(in) :: kind, scheme
      integer, intent(in) :: elements, ppc, steps
      type(config_t) :: config
      config%elements = elements
      config%particles_per_element = ppc
      config%dt_fraction = 0.2_dp
      config%scheme = scheme
      config%history = .false.
      select case (trim(kind))
      case ('bar_generic')
         config%kernels = 'generic'
      case ('bar_pic', 'bar_blend', 'bar_apic')
         config%transfer = kind(5:)
         config%flip_fraction = 0.95_dp
      case ('bar_total')
         config%formulation = 'total'
      case ('bar_cpdi')
         config%shape = 'cpdi'
      case ('bar_xpic2', 'bar_fmpm2')
         config%transfer = kind(5:8)
         config%xpic_order = 2
         config%fmpm_order = 2
      case ('bar_asflip')
         config%transfer = 'asflip'
         config%asflip_alpha = 0.99_dp
      case ('column')
         call set(config, [character(len=128) :: "scene.kind='column'"])
      case ('manufactured')
         call set(config, [character(len=128) :: "scene.kind='manufactured'", 'scene.length=1.0', 'scene.youngs_modulus=1.0e7', &
                   'scene.density=1000.0', 'scene.amplitude=1.0e-6'])
      case ('composite_bar')
         call set(config, [character(len=128) :: "scene.kind='composite_bar'", 'scene.lengths=1.0, 1.0', &
                   'scene.youngs_moduli=16.0e6, 1.0e6', 'scene.densities=1000.0, 1000.0', 'scene.drive_velocity=0.01'])
      case ('impact_frictionless', 'impact_none')
         call set(config, [character(len=128) :: "scene.kind='impact'", 'scene.lengths=1.0, 1.0', &
                   'scene.youngs_moduli=200.0e9, 200.0e9', 'scene.densities=7800.0, 7800.0', 'scene.velocities=1.0, -1.0', &
                   "scene.contact='"//trim(kind(8:))//"'"])
      end select
      call resolve_config(config)
      config%periods = -huge(1.0_dp)
      config%end_time = steps*config%dt
      call resolve_config(config)
   end function run_config

   !> `config` with variables set ('group.name=value').
   subroutine set(config, assignments)
      type(config_t), intent(inout) :: config
      character(len=*), intent(in) :: assignments(:)
      type(error_t), allocatable :: error
      call set_config_values(config, assignments, error)
      if (allocated(error)) error stop 'benchmark configuration refused: '//error%message
   end subroutine set

   !> The bar of `config` (its default scene).
   function bar_of(config) result(bar)
      type(config_t), intent(in) :: config
      type(bar_t) :: bar
      class(scene_t), allocatable :: scene
      type(error_t), allocatable :: error
      call config%scene%make(config, scene, error)
      select type (scene)
      type is (bar_t)
         bar = scene
      class default
         error stop 'the benchmark runs the bar'
      end select
   end function bar_of

   function scene_name(config) result(name)
      type(config_t), intent(in) :: config
      character(len=:), allocatable :: name
      name = trim(config%scene_kind)
      select type (input => config%scene)
      type is (impact_input_t)
         name = name//'_'//trim(input%contact)
      end select
   end function scene_name

   !> One whole run (run_simulation, no history) and its CPU time (one thread).
   subroutine timed_run(config, result, seconds)
      type(config_t), intent(in) :: config
      type(run_result_t), intent(out) :: result
      real(dp), intent(out) :: seconds
      type(error_t), allocatable :: error
      real(dp) :: start
      start = clock(1)
      call run_simulation(config, result, error, record_history=.false., processor_time=.true.)
      seconds = clock(1) - start
      if (allocated(error)) error stop 'run failed'
      if (result%status /= 0) error stop 'benchmark run stopped by a guard'
   end subroutine timed_run

   !> The bytes per particle a run of `config` holds: its particle arrays (those the scene allocates and,
   !> on the generic path, per-particle mass and volume; the elastoplastic law's state), the fused path's
   !> per-particle forces, APIC's
   !> velocity gradients, and the generic path's shape cache (first node, weights and gradients of the
   !> support, three columns of scratch, APIC's start positions, GIMP's half-lengths, CPDI's corners and
   !> corner indices, ASFLIP's start-of-step J; XPIC's and FMPM's scratch is the grid's, not per particle).
   real(dp) function run_bytes(config) result(per_particle)
      type(config_t), intent(in) :: config
      class(scene_t), allocatable :: scene
      type(particles_t) :: particles
      type(fused_box_t) :: box
      type(error_t), allocatable :: error
      integer(i8) :: bytes
      integer :: kind, transfer
      logical :: fused
      call config%scene%make(config, scene, error)
      if (allocated(error)) error stop 'scene failed'
      call scene%place_particles(config, particles, error)
      if (allocated(error)) error stop 'particles failed'
      kind = shape_id(config%shape)
      transfer = transfer_id(config%transfer)
      box = fused_choose(kind, transfer, config%flip_fraction, scene%fused_applies(), scene%body_fields, &
                         scene, particles, material_of(config), trim(config%formulation) == 'total', &
                         scheme_id(config%scheme))
      fused = trim(config%kernels) == 'auto' .and. box%variant >= 0
      if (.not. fused) call per_particle_data(particles, error)
      bytes = 0
      bytes = bytes + real_bytes(particles%x)
      bytes = bytes + real_bytes(particles%x0)
      bytes = bytes + real_bytes(particles%v)
      bytes = bytes + real_bytes(particles%stress)
      bytes = bytes + real_bytes(particles%volume_ratio)
      bytes = bytes + real_bytes(particles%mass_of)
      bytes = bytes + real_bytes(particles%volume0_of)
      bytes = bytes + real_bytes(particles%youngs_modulus_of)
      bytes = bytes + int_bytes(particles%cell)
      bytes = bytes + int_bytes(particles%body)
      if (allocated(particles%attached)) bytes = bytes + storage_size(particles%attached, i8)/8* &
                                                      size(particles%attached, kind=i8)
      if (transfer == transfer_apic) bytes = bytes + 8_i8*particles%count
      if (trim(config%law) == 'elastoplastic') bytes = bytes + 16_i8*particles%count  ! (plastic strain, hardening)
      if (fused) then
         if (scene%has_particle_forces) bytes = bytes + 8_i8*particles%count
      else
         bytes = bytes + (4_i8 + 16_i8*shape_support(kind) + 24_i8)*particles%count
         if (transfer == transfer_apic) bytes = bytes + 8_i8*particles%count
         if (kind == shape_ugimp .or. kind == shape_cpgimp) bytes = bytes + 8_i8*particles%count
         if (kind == shape_cpdi) then
            bytes = bytes + 12_i8*particles%count ! (corners and corner index)
            ! CPDI's lean step holds no shape cache (first node, weights, gradients), and the corners' moved
            ! positions
            if (trim(config%kernels) == 'auto' .and. cpdi_fast(scheme_id(config%scheme), transfer, &
                                                                 trim(config%formulation) == 'total', particles, scene)) &
               bytes = bytes - (4_i8 + 16_i8*shape_support(kind) - 8_i8)*particles%count
         end if
         if (transfer == transfer_asflip) bytes = bytes + 8_i8*particles%count
      end if
      per_particle = real(bytes, dp)/particles%count
   end function run_bytes

   integer(i8) function real_bytes(a)
      real(dp), allocatable, intent(in) :: a(:)
      real_bytes = 0
      if (allocated(a)) real_bytes = storage_size(a, i8)/8*size(a, kind=i8)
   end function real_bytes

   integer(i8) function int_bytes(a)
      integer, allocatable, intent(in) :: a(:)
      int_bytes = 0
      if (allocated(a)) int_bytes = storage_size(a, i8)/8*size(a, kind=i8)
   end function int_bytes
   !> A clock for the timed loops: with one thread the process's CPU time (time-slicing on a shared
   !> host then does not count; paired ratios of the same runs scattered 3x less than by wall clock),
   !> with more threads the wall-clock time.
   real(dp) function clock(threads)
      integer, intent(in) :: threads
      if (threads == 1) then
         call cpu_time(clock)
      else
         clock = omp_get_wtime()
      end if
   end function clock
end program mpm1d_bench
