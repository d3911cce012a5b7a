!> The vibrating bar against its exact solution: verification case, second-order convergence,
!> energy behaviour of USF and USL over 100 periods, step count robust to round-off.
program test_bar_exact
   use mpm_kinds, only: dp
   use mpm_errors, only: error_t
   use mpm_config, only: config_t, resolve_config
   use mpm_simulation, only: run_result_t, run_simulation
   use mpm_diagnostics, only: status_ok, status_left_grid, status_energy_growth, status_cell_crossing, status_name
   use mpm_testing, only: tester_t, tester
   use mpm_testing_runs, only: set_value
   use mpm_scene_bar, only: bar_t, bar_init, bar_input_t
   use mpm_scene, only: sine_profile
   use mpm_particles, only: particles_t
   use mpm_strings, only: str
   implicit none
   type(tester_t) :: t
   type(run_result_t) :: r
   real(dp) :: errors(3), order, ratio_first, ratio_last
   integer :: i, k
   character(len=4), parameter :: schemes(2) = ['usf ', 'usl '], schemes3(3) = ['usf ', 'usl ', 'musl']
   character(len=7), parameter :: kernel_paths(2) = ['auto   ', 'generic']

   t = tester('test_bar_exact')

   ! Verification case of the paper (Fig. 3b): 20 elements, 1 particle, 10 % of dx/c, 2 periods.
   if (t%case('verification')) then
      do i = 1, 2
         r = run(trim(schemes(i)), 20, 1, 0.1_dp, 2.0_dp, .true.)
         call t%check(trim(schemes(i))//' verification case completes', r%status == status_ok)
         call t%check(trim(schemes(i))//' 2 periods at 10% of dx/c take 8*20/0.1 = 1600 steps', r%steps == 1600)
         call t%check_close(trim(schemes(i))//' relative error well under 2 %', r%relative_error, 0.0_dp, atol=0.015_dp)
         call t%check(trim(schemes(i))//' error is not trivially zero', r%relative_error > 1.0e-4_dp)
         ! u_cm(t) follows the exact sine: its peak is within 2 % of the exact amplitude
         call t%check_close(trim(schemes(i))//' peak u_cm', maxval(r%history%ucm), r%ucm_amplitude, rtol=0.02_dp)
         call t%check('history has one entry per step plus t = 0', r%history%recorded == 1601)
      end do
   end if

   ! Second-order convergence with element size: USL, 2 particles per element, 1 % of dx/c.
   if (t%case('convergence_order')) then
      do i = 1, 3
         r = run('usl', 20*2**(i - 1), 2, 0.01_dp, 2.0_dp, .false.)
         errors(i) = r%max_error
      end do
      do i = 1, 2
         order = log(errors(i)/errors(i + 1))/log(2.0_dp)
         call t%check('USL convergence order in [1.8, 2.2]', order >= 1.8_dp .and. order <= 2.2_dp, &
                      'measured order '//real_text(order))
      end do
   end if

   ! Energy over 100 periods at 10 % of dx/c (Bardenhagen 2002): USF shows no systematic loss,
   ! USL dissipates. Period averages remove the oscillation within a period.
   if (t%case('energy_100_periods')) then
      r = run('usf', 20, 1, 0.1_dp, 100.0_dp, .true.)
      call period_means(r, ratio_first, ratio_last)
      call t%check_close('USF final energy within 1 % of the initial', r%final_energy, r%initial_energy, rtol=0.01_dp)
      call t%check_close('USF no systematic loss (period means, last/first)', ratio_last/ratio_first, 1.0_dp, atol=1.0e-4_dp)
      r = run('usl', 20, 1, 0.1_dp, 100.0_dp, .true.)
      call period_means(r, ratio_first, ratio_last)
      call t%check('USL loses energy (period means, last/first < 0.997)', ratio_last/ratio_first < 0.997_dp, &
                   'ratio '//real_text(ratio_last/ratio_first))
      call t%check('USL loss is gradual (last/first > 0.98)', ratio_last/ratio_first > 0.98_dp)
   end if

   ! The grid domain extends beyond the free end: at v0 = 0.01 c (end amplitude v0/omega = 0.01 c/(beta c)
   ! = 0.01*50/pi = 0.16 m, under one cell of 1.25 m: margin 1 + 2 cells) USF and MUSL run 2 periods on
   ! 20 elements x 4 particles; USL may meet its instability at a node a particle has just entered (the
   ! energy guard stops it and says so); with the grid ending at the bar (margin_cells = 0, as before)
   ! every scheme stops with left_grid.
   if (t%case('margin_beyond_free_end')) then
      do i = 1, 3
         r = run(trim(schemes3(i)), 20, 4, 0.1_dp, 2.0_dp, .false., v0=0.01_dp*sqrt(200.0e9_dp/7800.0_dp))
         if (trim(schemes3(i)) == 'usl') then
            call t%check('usl v0 = 0.01c, 20 x 4: completes or stops on energy growth at a nearly empty node', &
                         r%status == status_ok .or. (r%status == status_energy_growth .and. &
                                                     r%trip%node_mass_ratio < 0.01_dp), 'status '//status_name(r%status))
         else
            call t%check(trim(schemes3(i))//' v0 = 0.01c, 20 x 4, 2 periods completes', r%status == status_ok, &
                         'status '//status_name(r%status))
         end if
         call t%check(trim(schemes3(i))//' v0 = 0.01c: grid domain of 20 + 3 cells', &
                      abs(r%domain(2) - 23*25.0_dp/20) < 1.0e-12_dp .and. r%domain(1) == 0.0_dp)
         r = run(trim(schemes3(i)), 20, 4, 0.1_dp, 2.0_dp, .false., v0=0.01_dp*sqrt(200.0e9_dp/7800.0_dp), margin=0)
         call t%check(trim(schemes3(i))//' v0 = 0.01c with margin_cells = 0 leaves the grid', &
                      r%status == status_left_grid .and. r%trip%domain(2) == 25.0_dp)
      end do
   end if

   ! The cell-crossing guard names the particle that moved furthest: at v0 = 2000 m/s (0.4 c) the first
   ! step moves the bar's free end (the last particle, x nearest L in the first mode) 0.2 cells at half
   ! of dx/c, beyond a limit of 0.1; the fused kernels name it as the generic path does.
   if (t%case('cell_crossing_particle')) then
      do i = 1, 2
         do k = 1, 2
            r = run(trim(schemes(i)), 10, 2, 0.5_dp, 2.0_dp, .false., v0=2000.0_dp, max_move=0.1_dp, &
                    kernels=trim(kernel_paths(k)))
            call t%check(trim(schemes(i))//', '//trim(kernel_paths(k))//': cell_crossing at step 1', &
                         r%status == status_cell_crossing .and. r%trip%step == 1, 'status '//status_name(r%status)// &
                         ' at step '//str(r%trip%step))
            call t%check(trim(schemes(i))//', '//trim(kernel_paths(k))//': names the last particle', &
                         r%trip%particle == 20, 'particle '//str(r%trip%particle))
            call t%check(trim(schemes(i))//', '//trim(kernel_paths(k))//': on the path asked', &
                         r%fused .eqv. (trim(kernel_paths(k)) == 'auto'))
         end do
      end do
   end if

   ! The initial velocity of a particle does not depend on how many particles there are or where
   ! its array lies in memory: each equals v0 sin(beta x) of that particle evaluated alone (the
   ! vectorised sin of glibc differs from the scalar one in the last bit for some arguments, and a
   ! vectorised array splits between the two by length and alignment: the sweeps on two threads were
   ! not reproducible).
   if (t%case('initial_velocities')) call check_initial_velocities()

   call t%finish()

contains

   subroutine check_initial_velocities()
      type(config_t) :: config
      type(bar_t) :: bar
      type(particles_t) :: particles
      type(error_t), allocatable :: error
      real(dp) :: alone(1)
      integer :: ppc, p, differ, total
      differ = 0
      total = 0
      do ppc = 1, 17
         config%elements = 7
         config%particles_per_element = ppc
         call resolve_config(config)
         select type (input => config%scene)
         type is (bar_input_t)
            bar = bar_init(input%length, input%youngs_modulus, input%density, input%velocity_amplitude, input%mode)
         end select
         call bar%place_particles(config, particles, error)
         if (allocated(error)) error stop 'particles not placed'
         do p = 1, particles%count
            call sine_profile(bar%velocity_amplitude, bar%beta, particles%x(p:p), alone)
            total = total + 1
            if (particles%v(p) /= alone(1)) differ = differ + 1
         end do
      end do
      call t%check('each initial velocity equals its particle''s alone (7 elements, 1-17 per element)', &
                   differ == 0 .and. total == 7*17*18/2, str(differ)//' of '//str(total)//' differ')
   end subroutine check_initial_velocities

   function run(scheme, elements, ppc, fraction, periods, history, v0, margin, max_move, kernels) result(res)
      character(len=*), intent(in) :: scheme
      integer, intent(in) :: elements, ppc
      real(dp), intent(in) :: fraction, periods
      logical, intent(in) :: history
      real(dp), intent(in), optional :: v0, max_move
      integer, intent(in), optional :: margin
      character(len=*), intent(in), optional :: kernels
      type(run_result_t) :: res
      type(config_t) :: config
      type(error_t), allocatable :: error
      config%scheme = scheme
      config%elements = elements
      config%particles_per_element = ppc
      config%dt_fraction = fraction
      config%periods = periods
      if (present(v0)) call set_value(config, 'scene.velocity_amplitude='//str(v0))
      if (present(margin)) config%margin_cells = margin
      if (present(max_move)) config%max_cell_move = max_move
      if (present(kernels)) config%kernels = kernels
      call resolve_config(config)
      call run_simulation(config, res, error, record_history=history)
      if (allocated(error)) error stop 'run failed to start'
   end function run

   !> Mean total energy over the first and the last period, relative to the initial energy.
   subroutine period_means(res, first, last)
      type(run_result_t), intent(in) :: res
      real(dp), intent(out) :: first, last
      integer :: n, per
      n = res%history%recorded
      per = (n - 1)/100
      associate (e => res%history%kinetic_energy(0:n - 1) + res%history%strain_energy(0:n - 1))
         first = sum(e(1:per))/per/res%initial_energy
         last = sum(e(n - per:n - 1))/per/res%initial_energy
      end associate
   end subroutine period_means

   function real_text(x) result(text)
      real(dp), intent(in) :: x
      character(len=24) :: text
      write (text, '(g0.6)') x
   end function real_text
end program test_bar_exact
