!> Test helpers that run simulations (they use the run layer, so only tests of whole runs use them):
!> the fused kernels against the generic path, a run from a configuration, and mesh series' errors and orders.
module mpm_testing_runs
   use mpm_kinds, only: dp
   use mpm_strings, only: str
   use mpm_simulation, only: run_result_t, run_simulation
   use mpm_config, only: config_t, resolve_config, set_config_values, new_config
   use mpm_errors, only: error_t
   use mpm_diagnostics, only: status_ok
   use mpm_transfer, only: parallel_threshold
   use mpm_testing, only: tester_t
   use omp_lib, only: omp_set_num_threads
   implicit none
   private
   public :: check_paths_agree, check_fused_run, check_fused_config, run_resolved, set_values, set_value
   public :: mesh_errors, observed_orders, listed, convergence_bar, moving_bar, set_bar_speed
   !> c = sqrt(E/rho) of the vibrating bar's defaults (E = 200 GPa, rho = 7800 kg/m^3).
   real(dp), parameter, public :: bar_wave_speed = sqrt(200.0e9_dp/7800.0_dp)

contains

   !> The vibrating bar (its defaults) under `scheme` on `elements` x `ppc`, dt = `fraction` dx/c, for
   !> `periods`, at v0 = `speed` c (from about 0.01 c its particles cross cells).
   function moving_bar(scheme, elements, ppc, fraction, periods, speed) result(config)
      character(len=*), intent(in) :: scheme
      integer, intent(in) :: elements, ppc
      real(dp), intent(in) :: fraction, periods, speed
      type(config_t) :: config
      config = new_config()
      config%scheme = scheme
      config%elements = elements
      config%particles_per_element = ppc
      config%dt_fraction = fraction
      config%periods = periods
      call set_bar_speed(config, speed)
   end function moving_bar

   !> The bar's velocity amplitude v0 = `speed` c (c of the bar's defaults).
   subroutine set_bar_speed(config, speed)
      type(config_t), intent(inout) :: config
      real(dp), intent(in) :: speed
      call set_value(config, 'scene.velocity_amplitude='//str(speed*bar_wave_speed))
   end subroutine set_bar_speed

   !> `config` with variables set from assignments 'group.name=value' (mpm_config's set_config_values: a
   !> kind among them first); one it refuses ends the test program (error stop naming it).
   subroutine set_values(config, assignments)
      type(config_t), intent(inout) :: config
      character(len=*), intent(in) :: assignments(:)
      type(error_t), allocatable :: error
      call set_config_values(config, assignments, error)
      if (allocated(error)) then
         write (*, '(a)') 'set_values: '//error%message
         error stop 'set_values: an assignment was refused'
      end if
   end subroutine set_values

   !> set_values of one assignment (a value formed at run time: an array constructor of such strings is
   !> one that gfortran 12 can get wrong).
   subroutine set_value(config, assignment)
      type(config_t), intent(inout) :: config
      character(len=*), intent(in) :: assignment
      character(len=len(assignment)) :: one(1)
      one(1) = assignment
      call set_values(config, one)
   end subroutine set_value

   !> A run on the fused kernels and the same run on the generic path (`kernels='generic'`) agree: the
   !> paths were the ones asked for, same status and steps, u_cm histories equal to round-off and the
   !> last kinetic energies to 1e-10. The tolerance on u_cm is 1e-12 of the exact amplitude plus two
   !> ulps of the body length per particle: u_cm is a mean of x - X with x up to L, so one ulp of one
   !> particle's position moves it by spacing(L)/N, which for few particles and small amplitudes is more
   !> than 1e-12 of the amplitude.
   subroutine check_paths_agree(t, label, fused, generic, length)
      type(tester_t), intent(inout) :: t
      character(len=*), intent(in) :: label
      type(run_result_t), intent(in) :: fused, generic
      real(dp), intent(in) :: length
      real(dp) :: tolerance, worst
      integer :: n
      call t%check(label//'auto chose the fused kernels, generic the generic path', fused%fused .and. .not. generic%fused)
      call t%check(label//'same status and steps', fused%status == generic%status .and. &
                   fused%steps_done == generic%steps_done .and. fused%history%recorded == generic%history%recorded)
      n = min(fused%history%recorded, generic%history%recorded)
      tolerance = 1.0e-12_dp*abs(fused%ucm_amplitude) + 2*spacing(length)/fused%particles
      worst = maxval(abs(fused%history%ucm(0:n - 1) - generic%history%ucm(0:n - 1)))
      call t%check(label//'u_cm histories agree to round-off', worst <= tolerance, &
                   'largest difference '//str(worst)//' m, tolerance '//str(tolerance)//' m')
      call t%check_close(label//'kinetic energy histories', generic%history%kinetic_energy(n - 1), &
                         fused%history%kinetic_energy(n - 1), rtol=1.0e-10_dp)
   end subroutine check_paths_agree

   !> `given`, resolved (its derived quantities from the variables set), run with its history; a run
   !> that cannot start ends the test program (error stop naming the run's error).
   function run_resolved(given) result(res)
      type(config_t), intent(in) :: given
      type(run_result_t) :: res
      type(config_t) :: config
      type(error_t), allocatable :: error
      config = given
      call resolve_config(config)
      call run_simulation(config, res, error, record_history=.true.)
      if (allocated(error)) error stop 'run_resolved: the run failed to start'
   end function run_resolved

   !> The bar (scheme, shape, elements x ppc, dt fraction, amplitude v0, periods) run on the fused
   !> kernels and on the generic path agree: check_fused_config.
   subroutine check_fused_run(t, scheme, shape, elements, ppc, fraction, v0, periods, segments)
      type(tester_t), intent(inout) :: t
      character(len=*), intent(in) :: scheme, shape
      integer, intent(in) :: elements, ppc
      real(dp), intent(in) :: fraction, v0, periods
      logical, intent(in), optional :: segments
      type(config_t) :: config
      config%scheme = scheme
      config%shape = shape
      config%elements = elements
      config%particles_per_element = ppc
      config%dt_fraction = fraction
      call set_value(config, 'scene.velocity_amplitude='//str(v0))
      config%periods = periods
      call check_fused_config(t, scheme//' '//shape//' '//str(elements)//' x '//str(ppc)//' k '//str(fraction)// &
                              ' v0 '//str(v0)//': ', config, segments)
   end subroutine check_fused_run

   !> `given` run on the fused kernels (1 thread) and on the generic path agree (check_paths_agree). With
   !> `segments`, the run must be large enough to be cut into segments (`parallel_threshold` particles),
   !> and the fused run on 2 threads must give the 1-thread histories of u_cm and the energies bit for bit.
   subroutine check_fused_config(t, label, given, segments)
      type(tester_t), intent(inout) :: t
      character(len=*), intent(in) :: label
      type(config_t), intent(in) :: given
      logical, intent(in), optional :: segments
      type(run_result_t) :: fused, generic, two
      type(config_t) :: config
      type(error_t), allocatable :: error
      config = given
      call resolve_config(config)
      call omp_set_num_threads(1)
      call run_simulation(config, fused, error, record_history=.true.)
      if (allocated(error)) error stop 'check_fused_config: the run failed to start'
      config%kernels = 'generic'
      call run_simulation(config, generic, error, record_history=.true.)
      call check_paths_agree(t, label, fused, generic, maxval(abs(fused%domain)))
      if (.not. present(segments)) return
      if (segments) then
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
   end subroutine check_fused_config

   !> The linear-law bar of the cures' convergence checks (docs/theory.md, The cures): USL, FLIP, 2 particles
   !> per element, dt = 0.1 dx/c, one period, with `formulation` and `shape`.
   function convergence_bar(formulation, shape) result(config)
      character(len=*), intent(in) :: formulation, shape
      type(config_t) :: config
      config%formulation = formulation
      config%shape = shape
      config%law = 'linear'
      config%scheme = 'usl'
      config%particles_per_element = 2
      config%dt_fraction = 0.1_dp
      config%periods = 1.0_dp
   end function convergence_bar

   !> The relative errors of `config` run on each of `meshes` elements (huge where a run did not complete).
   function mesh_errors(config, meshes) result(errors)
      type(config_t), intent(in) :: config
      integer, intent(in) :: meshes(:)
      real(dp) :: errors(size(meshes))
      type(config_t) :: case
      type(run_result_t) :: result
      type(error_t), allocatable :: error
      integer :: k
      case = config
      do k = 1, size(meshes)
         case%elements = meshes(k)
         call resolve_config(case)
         call run_simulation(case, result, error, record_history=.false.)
         errors(k) = merge(result%relative_error, huge(1.0_dp), result%status == status_ok .and. &
                           .not. allocated(error))
      end do
   end function mesh_errors

   !> The observed orders between successive meshes, each twice the last.
   pure function observed_orders(errors) result(orders)
      real(dp), intent(in) :: errors(:)
      real(dp) :: orders(size(errors) - 1)
      orders = log(errors(:size(errors) - 1)/errors(2:))/log(2.0_dp)
   end function observed_orders

   !> Numbers as text for a check's detail: ' 1.0E-3 2.5E-4 ...'.
   function listed(values) result(text)
      real(dp), intent(in) :: values(:)
      character(len=:), allocatable :: text
      integer :: k
      text = ''
      do k = 1, size(values)
         text = text//' '//str(values(k))
      end do
   end function listed
end module mpm_testing_runs
