!> The fused kernels' variants (mpm_fused's fused_choose: the bar's kernels with a scene's grid loads, and
!> the hat's variants) against the generic path, which is their definition, run by run with
!> `kernels='generic'` as the only difference:
!> - the bar with PIC, the PIC/FLIP blend and APIC (variants pic, blend, apic);
!> - the column (its weight a grid load on the bar's kernels; linear, and quadratic B-splines, whose
!>   load is reflected at the mirrored fixed end);
!> - the composite bar (per-particle masses and moduli; the driven end a grid load);
!> - the manufactured solution (per-particle forces mapped in the passes);
!> - the impact, frictionless (bodies on stacked fields, the contact correction between passes) and
!>   stuck (one field, a grid origin left of x = 0);
!> each with USF, USL and MUSL: the path asked for, same status and steps, u_cm histories equal to
!> round-off and the last kinetic energies to 1e-10 (mpm_testing_runs' check_paths_agree, its u_cm
!> tolerance taken from the largest |u_cm| of the generic run where the scene's amplitude is not a
!> displacement), and the scene's error measure to 1e-9 relative; with law = 'linear' the same
!> comparison (the fused kernels' stress update takes every law) for the bar with every shape, the
!> composite and the manufactured solution; with law = 'elastoplastic', yielding, for the bar with every
!> shape and every transfer of the hat, the column, the composite bar (each segment its own yield stress)
!> and the frictionless impact (each bar its own), the law's report (plastic work, largest plastic strain,
!> yielded fraction) to 1e-9 too; an elastoplastic bar that never yields gives the fused Hencky bar's
!> histories bit for bit (the radial return adds exact zeros), every shape. The plastic wave (a driven
!> end) runs on the generic path. The frictionless impact also takes snapshots after contact: their
!> nodal velocities (the run's grid, the bodies' fields summed only when a snapshot reads it) equal the
!> generic path's to round-off.
!> The scenes' reports agree too (reports_agree: the impact's contact times, stress and velocities, which
!> on stacked fields come from the fused kernels' per-body sums).
!> Small runs: seconds.
program test_fused_scenes
   use mpm_kinds, only: dp
   use mpm_scene_bar, only: bar_input_t
   use mpm_errors, only: error_t
   use mpm_config, only: config_t, resolve_config, new_config
   use mpm_simulation, only: run_result_t, run_simulation
   use mpm_strings, only: str
   use mpm_testing, only: tester_t, tester
   use mpm_testing_runs, only: check_paths_agree, set_values, set_value
   implicit none
   type(tester_t) :: t
   character(len=4), parameter :: schemes(3) = ['usf ', 'usl ', 'musl']
   character(len=5), parameter :: transfers(3) = ['pic  ', 'blend', 'apic ']
   character(len=8), parameter :: shapes(5) = [character(len=8) :: 'linear', 'ugimp', 'cpgimp', 'bspline2', 'bspline3']
   type(config_t) :: config
   integer :: i, j

   t = tester('test_fused_scenes')
   if (t%case('bar_transfers')) then
      do i = 1, size(schemes)
         do j = 1, size(transfers)
            config = new_config()
            config%scheme = trim(schemes(i))
            config%transfer = trim(transfers(j))
            config%flip_fraction = 0.75_dp
            config%elements = 30
            config%particles_per_element = 3
            config%dt_fraction = 0.3_dp
            call set_values(config, ['scene.velocity_amplitude=5.0'])
            config%periods = 1.0_dp
            call compare('bar '//trim(transfers(j)), config)
            call yielding(config)
            call compare('bar '//trim(transfers(j))//', law elastoplastic', config)
         end do
      end do
   end if
   if (t%case('column')) then
      do i = 1, size(schemes)
         config = new_config()
         call set_values(config, ["scene.kind='column'"])
         config%scheme = trim(schemes(i))
         config%elements = 40
         config%particles_per_element = 2
         config%dt_fraction = 0.3_dp
         config%periods = 1.0_dp
         call compare('column', config)
         config%shape = 'bspline2'
         call compare('column bspline2', config)
         config%law = 'elastoplastic'  ! (the dynamic load of the weight yields the lower quarter)
         call set_values(config, ['material.yield_stress=2.5e6'])
         call set_values(config, ['material.hardening_modulus=1.0e9'])
         call compare('column bspline2, law elastoplastic', config)
         config%shape = 'linear'
         call compare('column, law elastoplastic', config)
      end do
   end if
   if (t%case('composite')) then
      do i = 1, size(schemes)
         config = new_config()
         call set_values(config, ["scene.kind='composite_bar'"])
         config%scheme = trim(schemes(i))
         call set_values(config, ['scene.lengths=1.0, 1.0'])
         call set_values(config, ['scene.youngs_moduli=16.0e6, 1.0e6'])
         call set_values(config, ['scene.densities=1000.0, 1000.0'])
         call set_values(config, ['scene.drive_velocity=0.01'])
         config%elements = 45  ! (the interface inside an element: particles of both materials share it)
         config%particles_per_element = 3
         config%dt_fraction = 0.3_dp
         config%periods = 0.5_dp
         call compare('composite', config, by_largest=.true.)
         config%law = 'linear'
         call compare('composite, law linear', config, by_largest=.true.)
         ! each segment its yield stress and hardening modulus (per particle), both below the stresses the
         ! drive makes (1.3e3 Pa in the stiff segment, 3.2e2 Pa in the soft one): both segments yield
         config%law = 'elastoplastic'
         call set_values(config, ['material.yield_stresses=8.0e2, 2.0e2'])
         call set_values(config, ['material.hardening_moduli=1.0e6, 0.0'])
         call compare('composite, law elastoplastic', config, by_largest=.true.)
      end do
   end if
   if (t%case('manufactured')) then
      do i = 1, size(schemes)
         config = new_config()
         call set_values(config, ["scene.kind='manufactured'"])
         config%scheme = trim(schemes(i))
         call set_values(config, ['scene.length=1.0'])
         call set_values(config, ['scene.youngs_modulus=1.0e7'])
         call set_values(config, ['scene.density=1000.0'])
         call set_values(config, ['scene.amplitude=1.0e-3'])
         config%elements = 30
         config%particles_per_element = 2
         config%dt_fraction = 0.2_dp
         config%periods = 1.0_dp
         call compare('manufactured', config)
         config%law = 'linear'
         call compare('manufactured, law linear', config)
      end do
   end if
   if (t%case('bar_shapes_law_linear')) then
      do i = 1, size(schemes)
         do j = 1, size(shapes)
            config = new_config()
            config%scheme = trim(schemes(i))
            config%shape = trim(shapes(j))
            config%law = 'linear'
            config%elements = 24
            config%particles_per_element = 2
            config%dt_fraction = 0.2_dp
            call set_values(config, ['scene.velocity_amplitude=5.0'])
            config%periods = 1.0_dp
            call compare('bar '//trim(shapes(j))//', law linear', config)
         end do
      end do
   end if
   if (t%case('bar_shapes_law_elastoplastic')) then
      do i = 1, size(schemes)
         do j = 1, size(shapes)
            config = new_config()
            config%scheme = trim(schemes(i))
            config%shape = trim(shapes(j))
            config%elements = 24
            config%particles_per_element = 2
            config%dt_fraction = 0.2_dp
            call set_values(config, ['scene.velocity_amplitude=5.0'])
            config%periods = 1.0_dp
            call yielding(config)
            call compare('bar '//trim(shapes(j))//', law elastoplastic', config)
            call never_yields('bar '//trim(shapes(j)), config)
         end do
      end do
   end if
   if (t%case('impact')) then
      do i = 1, size(schemes)
         config = new_config()
         call set_values(config, ["scene.kind='impact'"])
         config%scheme = trim(schemes(i))
         call set_values(config, ['scene.lengths=1.0, 0.7'])
         call set_values(config, ['scene.youngs_moduli=200.0e9, 50.0e9'])
         call set_values(config, ['scene.densities=7800.0, 31200.0'])  ! (equal impedances, as the scene requires)
         call set_values(config, ['scene.velocities=1.0, -1.0'])
         call set_values(config, ['scene.gap=0.0'])  ! (in contact from the start)
         config%elements = 40
         config%particles_per_element = 2
         config%dt_fraction = 0.2_dp
         config%periods = 1.0_dp
         call set_values(config, ["scene.contact='frictionless'"])
         call compare('impact frictionless', config, by_largest=.true., snapshots=.true.)
         config%law = 'elastoplastic'  ! (the contact stress rho c v = 3.9e7 Pa: both bars yield)
         call set_values(config, ['material.yield_stresses=2.0e7, 1.0e7'])
         call set_values(config, ['material.hardening_moduli=1.0e10, 2.0e9'])
         call compare('impact frictionless, law elastoplastic', config, by_largest=.true.)
         config%law = 'hencky'
         ! soft bars (c = 31.6 m/s) moving right that close a gap of 0.02 m, meet and part: their particles
         ! cross cells, so each body's nodes to solve move with it (fused_step's active_nodes), and the nodes
         ! a body left must be solved once more (to zeros) or their old values reach the contact correction
         ! and the snapshots. (USF: no stacked-field solve restricted to active nodes. 4 particles per
         ! element: at 2, USL's runs of this case stop at J <= 0 on both paths.)
         call set_values(config, ['scene.lengths=1.0, 1.0'])
         call set_values(config, ['scene.youngs_moduli=1.0e6, 1.0e6'])
         call set_values(config, ['scene.densities=1000.0, 1000.0'])
         call set_values(config, ['scene.velocities=1.4, 0.6'])
         call set_values(config, ['scene.gap=0.02'])
         config%periods = 2.0_dp
         config%particles_per_element = 4
         if (trim(schemes(i)) /= 'usf') call compare('impact frictionless, soft bars crossing cells', config, &
                                                      by_largest=.true., snapshots=.true.)
         config%particles_per_element = 2
         call set_values(config, ['scene.velocities=1.0, -1.0'])
         call set_values(config, ['scene.gap=0.0'])
         config%periods = 1.0_dp
         call set_values(config, ['scene.youngs_moduli=200.0e9, 200.0e9'])
         call set_values(config, ['scene.densities=7800.0, 7800.0'])
         call set_values(config, ['scene.lengths=1.0, 1.0'])
         call set_values(config, ["scene.contact='none'"])
         call compare('impact stuck', config, by_largest=.true.)
      end do
   end if
   if (t%case('plastic_wave')) then
      do i = 1, size(schemes)
         config = new_config()
         call set_values(config, ["scene.kind='plastic_wave'"])
         config%scheme = trim(schemes(i))
         config%law = 'elastoplastic'
         call set_values(config, ['scene.drive_velocity=20.0'])
         config%elements = 50
         config%particles_per_element = 2
         config%dt_fraction = 0.2_dp
         call on_generic_path('plastic wave (a driven end)', config)
      end do
   end if
   call t%finish()

contains

   !> `config` on the fused kernels (kernels='auto') and on the generic path agree (see the program's
   !> comment); `by_largest`: the u_cm tolerance from the generic run's largest |u_cm|.
   subroutine compare(what, config, by_largest, snapshots)
      character(len=*), intent(in) :: what
      type(config_t), intent(in) :: config
      logical, intent(in), optional :: by_largest, snapshots
      type(config_t) :: auto, generic_config, given
      type(run_result_t) :: fused, generic
      type(error_t), allocatable :: error
      character(len=:), allocatable :: label
      integer :: k
      real(dp) :: largest
      label = trim(config%scheme)//' '//what//': '
      given = config
      if (present(snapshots)) then ! at 0.4 and 0.8 of the run (the bodies in contact, then apart)
         call resolve_config(given)
         given%snapshot_count = 2
         given%snapshot_times(1:2) = [0.4_dp, 0.8_dp]*given%steps*given%dt
      end if
      auto = given
      auto%kernels = 'auto'
      call resolve_config(auto)
      call run_simulation(auto, fused, error, record_history=.true.)
      if (allocated(error)) error stop 'fused run failed to start'
      generic_config = given
      generic_config%kernels = 'generic'
      call resolve_config(generic_config)
      call run_simulation(generic_config, generic, error, record_history=.true.)
      if (allocated(error)) error stop 'generic run failed to start'
      if (present(by_largest)) then
         if (by_largest) fused%ucm_amplitude = maxval(abs(generic%history%ucm(0:generic%history%recorded - 1)))
      end if
      call check_paths_agree(t, label, fused, generic, maxval(abs(fused%domain)))
      call t%check_close(label//'error measure', fused%max_error, generic%max_error, rtol=1.0e-9_dp, &
                         atol=1.0e-14_dp*abs(generic%ucm_amplitude))
      call t%check(label//'status ok', fused%status == 0, 'status '//str(fused%status))
      call reports_agree(label, fused, generic)
      if (present(snapshots)) then
         call t%check(label//'two snapshots', size(fused%snapshots) == 2 .and. size(generic%snapshots) == 2)
         do k = 1, min(2, size(fused%snapshots), size(generic%snapshots))
            largest = maxval(abs(generic%snapshots(k)%grid_velocity))
            call t%check(label//'snapshot '//str(k)//' moving grid', largest > 0.1_dp, 'largest |v_I| '//str(largest))
            call t%check_close(label//'snapshot '//str(k)//' grid velocity = generic', &
                               maxval(abs(fused%snapshots(k)%grid_velocity - generic%snapshots(k)%grid_velocity)), 0.0_dp, &
                               atol=1.0e-9_dp*largest)
         end do
      end if
   end subroutine compare

   !> The scene's reports agree (the impact's contact start, end and time, largest compressive stress,
   !> final velocities: on stacked fields the fused kernels' per-body sums, else the particles') to 1e-9
   !> relative, and the total momentum's largest change is round-off on both paths (below 1e-13 of
   !> sum_b M_b |v_b|). final_momentum is not compared: where the bars' momenta cancel, it is round-off.
   subroutine reports_agree(label, fused, generic)
      character(len=*), intent(in) :: label
      type(run_result_t), intent(in) :: fused, generic
      integer :: k
      character(len=:), allocatable :: name
      call t%check(label//'the same reports', size(fused%report_names) == size(generic%report_names))
      if (size(fused%report_names) /= size(generic%report_names)) return
      do k = 1, size(generic%report_names)
         name = trim(generic%report_names(k))
         call t%check(label//'report '//name//' on both paths', trim(fused%report_names(k)) == name)
         select case (name)
         case ('final_momentum')
         case ('momentum_change')
            call t%check(label//'momentum change round-off', abs(fused%report_values(k)) < 1.0e-13_dp .and. &
                         abs(generic%report_values(k)) < 1.0e-13_dp, 'fused '//str(fused%report_values(k))// &
                         ', generic '//str(generic%report_values(k)))
         case default
            call t%check_close(label//'report '//name, fused%report_values(k), generic%report_values(k), &
                               rtol=1.0e-9_dp, atol=1.0e-300_dp)
         end select
      end do
   end subroutine reports_agree

   !> `config` with kernels='auto' runs on the generic path, and completes.
   subroutine on_generic_path(what, config)
      character(len=*), intent(in) :: what
      type(config_t), intent(in) :: config
      type(config_t) :: auto
      type(run_result_t) :: result
      type(error_t), allocatable :: error
      auto = config
      auto%kernels = 'auto'
      call resolve_config(auto)
      call run_simulation(auto, result, error, record_history=.false.)
      if (allocated(error)) error stop 'run failed to start'
      call t%check(trim(config%scheme)//' '//what//': on the generic path', .not. result%fused)
      call t%check(trim(config%scheme)//' '//what//': status ok', result%status == 0, 'status '//str(result%status))
   end subroutine on_generic_path

   !> `config` made elastoplastic and yielding: the bar's stress amplitude rho c v0 four times its yield
   !> stress, hardening modulus E/20.
   subroutine yielding(config)
      type(config_t), intent(inout) :: config
      real(dp) :: yield_stress, hardening_modulus
      config%law = 'elastoplastic'
      select type (bar => config%scene)
      type is (bar_input_t)
         yield_stress = 0.25_dp*sqrt(bar%youngs_modulus*bar%density)*bar%velocity_amplitude
         hardening_modulus = bar%youngs_modulus/20
      class default
         error stop 'yielding: the bar only'
      end select
      call set_value(config, 'material.yield_stress='//str(yield_stress))
      call set_value(config, 'material.hardening_modulus='//str(hardening_modulus))
   end subroutine yielding

   !> `config` (the bar) elastoplastic with a yield stress it never reaches, on the fused kernels: the
   !> histories of u_cm and the energies are the Hencky bar's bit for bit (the radial return of an elastic
   !> step subtracts and adds exact zeros, and the strain energy is written as hencky's), the plastic
   !> work zero, and the run on the fused kernels.
   subroutine never_yields(what, config)
      character(len=*), intent(in) :: what
      type(config_t), intent(in) :: config
      type(config_t) :: plastic, hencky
      type(run_result_t) :: a, b
      type(error_t), allocatable :: error
      character(len=:), allocatable :: label
      label = trim(config%scheme)//' '//what//' elastoplastic, never yielding: '
      hencky = config
      hencky%law = 'hencky'
      call resolve_config(hencky)
      call run_simulation(hencky, a, error, record_history=.true.)
      if (allocated(error)) error stop 'hencky run failed to start'
      plastic = config
      plastic%law = 'elastoplastic'
      call set_values(plastic, ['material.yield_stress=1.0e30'])
      call resolve_config(plastic)
      call run_simulation(plastic, b, error, record_history=.true.)
      if (allocated(error)) error stop 'elastoplastic run failed to start'
      call t%check(label//'both on the fused kernels', a%fused .and. b%fused)
      call t%check(label//'same steps', a%steps_done == b%steps_done .and. a%history%recorded == b%history%recorded)
      if (a%history%recorded /= b%history%recorded) return
      call t%check(label//'u_cm, kinetic and strain energy histories = hencky''s bit for bit', &
                   all(a%history%ucm == b%history%ucm) .and. all(a%history%kinetic_energy == b%history%kinetic_energy) &
                   .and. all(a%history%strain_energy == b%history%strain_energy))
      call t%check(label//'no plastic work', all(b%history%plastic_work == 0.0_dp))
   end subroutine never_yields
end program test_fused_scenes
