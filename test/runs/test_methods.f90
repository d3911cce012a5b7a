!> The methods of docs/theory.md ("The cures") through the whole program, on the generic path:
!> - XPIC(1), FMPM(1) and ASFLIP with alpha = 0 reproduce PIC to round-off (u_cm histories, USF, USL and
!>   MUSL, the hat and the quadratic B-splines with their mirror ghost, the bar at v0 = 0.01 c where
!>   particles cross cells), and XPIC(2), FMPM(2) and ASFLIP(0.99) do not (the comparison can fail);
!> - the total-Lagrangian bar of the linear law (USL, FLIP, 2 particles per element, dt = 0.1 dx/c, one
!>   period) converges at order 2 from 25 to 200 elements, and CPDI at order 2 on that bar and on the
!>   manufactured solution at A/L = 0.05 (F from 0.69 to 1.31), where the hat does not converge;
!> - long: both on that bar to 1600 elements with no floor (order at least 1.9 at every doubling from 100
!>   elements, the error at 1600 below 1e-6), where the hat stops at a floor of about 1.4e-5 (800 elements);
!> - the total-Lagrangian formulation: uGIMP and cpGIMP give the same bits (the reference box never changes),
!>   and the plastic wave's drive works on the reference grid (the run completes near its exact solution);
!> - CPDI: a domain stretched over more than the four nodes a particle touches stops the run with
!>   domain_stretched.
!> Agreement with an independent implementation at round-off: test/reference/check_reference.py.
program test_methods
   use mpm_kinds, only: dp
   use mpm_config, only: config_t, new_config
   use mpm_simulation, only: run_result_t
   use mpm_diagnostics, only: status_ok, status_name, status_domain_stretched
   use mpm_strings, only: str
   use mpm_testing, only: tester_t, tester
   use mpm_testing_runs, only: run_resolved, mesh_errors, observed_orders, listed, convergence_bar, set_values, &
                               moving_bar, set_bar_speed
   implicit none
   type(tester_t) :: t
   character(len=4), parameter :: schemes(3) = ['usf ', 'usl ', 'musl']
   character(len=8), parameter :: shapes(2) = ['linear  ', 'bspline2']
   integer :: i, j
   t = tester('test_methods')
   do i = 1, size(schemes)
      do j = 1, size(shapes)
         if (t%case('pic_'//trim(schemes(i))//'_'//trim(shapes(j)))) call reduce_to_pic(trim(schemes(i)), trim(shapes(j)))
      end do
   end do
   if (t%case('total_lagrangian_order')) call total_lagrangian_order()
   if (t%case('cpdi_order')) call cpdi_order()
   if (t%case('total_lagrangian_properties')) call total_lagrangian_properties()
   if (t%case('cpdi_stretched')) call cpdi_properties()
   if (t%case('no_floor_to_1600', long=.true.)) then
      call no_floor('total', 'linear', 'total-Lagrangian')
      call no_floor('updated', 'cpdi', 'CPDI')
   end if
   call t%finish()

contains

   !> The bar at v0 = 0.01 c, 12 elements x 3 particles, dt = 0.2 dx/c, half a period.
   function crossing_bar(scheme, shape, transfer) result(config)
      character(len=*), intent(in) :: scheme, shape, transfer
      type(config_t) :: config
      config = moving_bar(scheme, 12, 3, 0.2_dp, 0.5_dp, 0.01_dp)
      config%shape = shape
      config%transfer = transfer
      config%kernels = 'generic'
   end function crossing_bar

   !> The largest difference of two runs' u_cm histories over the exact amplitude.
   real(dp) function history_difference(a, b)
      type(run_result_t), intent(in) :: a, b
      history_difference = maxval(abs(a%history%ucm - b%history%ucm))/abs(a%ucm_amplitude)
   end function history_difference

   subroutine reduce_to_pic(scheme, shape)
      character(len=*), intent(in) :: scheme, shape
      type(run_result_t) :: pic
      type(config_t) :: config
      character(len=:), allocatable :: name
      name = scheme//' '//shape//': '
      pic = run_resolved(crossing_bar(scheme, shape, 'pic'))
      call t%check(name//'PIC completes', pic%status == status_ok, status_name(pic%status))
      config = crossing_bar(scheme, shape, 'xpic')
      config%xpic_order = 1
      call compare(name//'XPIC(1)', pic, config, .true.)
      config%xpic_order = 2
      call compare(name//'XPIC(2)', pic, config, .false.)
      config = crossing_bar(scheme, shape, 'fmpm')
      config%fmpm_order = 1
      call compare(name//'FMPM(1)', pic, config, .true.)
      config%fmpm_order = 2
      call compare(name//'FMPM(2)', pic, config, .false.)
      config = crossing_bar(scheme, shape, 'asflip')
      config%asflip_alpha = 0.0_dp
      call compare(name//'ASFLIP(0)', pic, config, .true.)
      config%asflip_alpha = 0.99_dp
      call compare(name//'ASFLIP(0.99)', pic, config, .false.)
   end subroutine reduce_to_pic

   !> The run of `config` against `pic`: the same u_cm history to round-off (`same`), or not.
   subroutine compare(what, pic, config, same)
      character(len=*), intent(in) :: what
      type(run_result_t), intent(in) :: pic
      type(config_t), intent(in) :: config
      logical, intent(in) :: same
      type(run_result_t) :: other
      real(dp) :: difference
      other = run_resolved(config)
      difference = history_difference(pic, other)
      if (same) then
         call t%check(what//' is PIC to round-off (u_cm history within 1e-12 of the amplitude)', &
                      other%status == status_ok .and. difference <= 1.0e-12_dp, str(difference))
      else
         call t%check(what//' is not PIC (u_cm history differs by more than 1e-6 of the amplitude)', &
                      other%status == status_ok .and. difference > 1.0e-6_dp, str(difference))
      end if
   end subroutine compare

   subroutine total_lagrangian_order()
      real(dp) :: errors(4)
      errors = mesh_errors(convergence_bar('total', 'linear'), [25, 50, 100, 200])
      call t%check('total Lagrangian, linear-law bar: order 2 from 25 to 200 elements (1.95 to 2.05)', &
                   all(abs(observed_orders(errors) - 2.0_dp) <= 0.05_dp), 'errors'//listed(errors)//'; orders'// &
                   listed(observed_orders(errors)))
   end subroutine total_lagrangian_order

   subroutine cpdi_order()
      real(dp) :: errors(4), large(3)
      type(config_t) :: config
      errors = mesh_errors(convergence_bar('updated', 'cpdi'), [25, 50, 100, 200])
      call t%check('CPDI, linear-law bar: order 2 from 25 to 200 elements (1.95 to 2.05)', &
                   all(abs(observed_orders(errors) - 2.0_dp) <= 0.05_dp), 'errors'//listed(errors)//'; orders'// &
                   listed(observed_orders(errors)))
      call set_values(config, ["scene.kind='manufactured'"])
      call set_values(config, ['scene.length=1.0'])
      call set_values(config, ['scene.youngs_modulus=1.0e7'])
      call set_values(config, ['scene.density=1000.0'])
      call set_values(config, ['scene.amplitude=0.05'])
      config%scheme = 'usl'
      config%particles_per_element = 2
      config%dt_fraction = 0.1_dp
      config%periods = 0.5_dp
      config%shape = 'cpdi'
      large = mesh_errors(config, [16, 32, 64])
      call t%check('CPDI, manufactured solution at A/L = 0.05: order 2 from 16 to 64 elements (1.9 to 2.1)', &
                   all(abs(observed_orders(large) - 2.0_dp) <= 0.1_dp), 'errors'//listed(large)//'; orders'// &
                   listed(observed_orders(large)))
      config%shape = 'linear'
      large = mesh_errors(config, [16, 32, 64])
      call t%check('the hat on the same runs does not converge (the check above can fail)', &
                   all(observed_orders(large) < 0.0_dp), 'errors'//listed(large)//'; orders'// &
                   listed(observed_orders(large)))
   end subroutine cpdi_order

   subroutine total_lagrangian_properties()
      type(config_t) :: config
      type(run_result_t) :: a, b
      config = crossing_bar('usl', 'ugimp', 'flip')
      config%formulation = 'total'
      a = run_resolved(config)
      config%shape = 'cpgimp'
      b = run_resolved(config)
      call t%check('total Lagrangian: uGIMP and cpGIMP give the same bits', a%status == status_ok .and. &
                   all(a%history%ucm == b%history%ucm) .and. a%max_error == b%max_error)
      config%formulation = 'updated'
      b = run_resolved(config)
      call t%check('... which the updated formulation does not (the check can fail)', &
                   any(a%history%ucm /= b%history%ucm))
      ! the plastic wave on the reference grid: the drive keeps the end particle at V
      config = new_config()
      call set_values(config, ["scene.kind='plastic_wave'"])
      config%law = 'elastoplastic'
      config%formulation = 'total'
      config%elements = 100
      config%particles_per_element = 2
      config%periods = 0.8_dp ! (its default: the exact solution holds until the precursor reaches the free end)
      a = run_resolved(config)
      call t%check('total Lagrangian plastic wave completes', a%status == status_ok, status_name(a%status))
      call t%check('... its relative error below 10 %', a%relative_error < 0.1_dp, str(a%relative_error))
   end subroutine total_lagrangian_properties

   subroutine cpdi_properties()
      type(config_t) :: config
      type(run_result_t) :: result
      ! the bar stretched beyond four nodes: one particle per element, a free end pulled far
      config = crossing_bar('usl', 'cpdi', 'flip')
      config%particles_per_element = 1
      call set_bar_speed(config, 2.0_dp)
      config%energy_growth_limit = 1.0e10_dp
      result = run_resolved(config)
      call t%check('CPDI: a domain stretched over more than four nodes stops the run with domain_stretched', &
                   result%status == status_domain_stretched, status_name(result%status))
   end subroutine cpdi_properties

   !> The bar of convergence_bar from 100 to 1600 elements: order 2 at every doubling, no floor.
   subroutine no_floor(formulation, shape, name)
      character(len=*), intent(in) :: formulation, shape, name
      integer, parameter :: meshes(5) = [100, 200, 400, 800, 1600]
      real(dp) :: errors(size(meshes))
      character(len=:), allocatable :: detail
      errors = mesh_errors(convergence_bar(formulation, shape), meshes)
      detail = 'errors'//listed(errors)//'; orders'//listed(observed_orders(errors))
      call t%check(name//' linear-law bar: order at least 1.9 at every doubling from 100 to 1600 elements', &
                   all(observed_orders(errors) >= 1.9_dp), detail)
      call t%check(name//' linear-law bar: relative error below 1e-6 at 1600 elements (the hat: 1.4e-5)', &
                   errors(size(errors)) < 1.0e-6_dp, detail)
   end subroutine no_floor
end program test_methods
