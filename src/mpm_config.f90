!> Namelist configuration of one run: read, validate (reporting every problem), resolve derived
!> quantities (wave speed, element size, time step, step count) and echo.
module mpm_config
   use, intrinsic :: ieee_arithmetic, only: ieee_is_finite
   use mpm_kinds, only: dp, i8, pi
   use mpm_errors, only: error_t, set_error, append_error
   use mpm_strings, only: str, lower
   use mpm_files, only: available_memory
   use mpm_particles, only: bytes_per_particle
   use mpm_shape, only: known_shapes, known_transfers
   use mpm_registry, only: parameter_t, nml_item_t, text_entry, int_entry, real_entry, real_list_entry, &
                           logical_entry, read_namelist, apply_items, check_parameter, find_parameter, group_namelist
   implicit none
   private
   public :: config_t, read_config, validate_config, resolve_config, write_config_namelist, config_namelist
   public :: default_config, config_summary, known_schemes
   public :: max_snapshots, unset, check_output_path
   public :: config_parameters, config_groups, group_help
   public :: step_count, stability_limit

   !> Sentinel for "not given" reals; no physical input takes this value.
   real(dp), parameter :: unset = -huge(1.0_dp)
   !> Most snapshot times one run accepts.
   integer, parameter :: max_snapshots = 64
   !> Schemes the code implements.
   character(len=*), parameter :: known_schemes = 'usf, usl, musl'
   !> The groups of one run's input, in the order of the echo and of --help.
   character(len=16), parameter :: config_groups(*) = [character(len=16) :: 'scene', 'discretisation', 'run', &
                                                        'output', 'guards']
   !> Largest number of particles or elements one run accepts (array indices are default integers).
   integer(i8), parameter :: max_count = int(huge(1), i8)
   !> Time-step fraction above which a run is refused outright (far beyond any stability limit).
   real(dp), parameter :: max_dt_fraction = 10.0_dp

   !> Everything one run needs to know; defaults are the paper's Table 1 and its verification case.
   type :: config_t
      ! &scene
      character(len=32) :: scene_kind = 'vibrating_bar'
      real(dp) :: length = 25.0_dp
      real(dp) :: youngs_modulus = 200.0e9_dp
      real(dp) :: density = 7800.0_dp
      real(dp) :: velocity_amplitude = 0.1_dp
      integer :: mode = 1
      ! &discretisation
      character(len=8) :: scheme = 'usl'
      integer :: elements = 20
      integer :: particles_per_element = 1
      real(dp) :: dt_fraction = 0.1_dp
      !> Empty grid cells beyond each free end of the body; -1: the scene's expected motion + 2 cells.
      integer :: margin_cells = -1
      !> 'auto': the fused linear kernels where they apply, else the generic path; 'generic': always generic.
      character(len=8) :: kernels = 'auto'
      !> Shape functions (mpm_shape) and the velocity transfer of G2P, with the FLIP share of 'blend'.
      character(len=8) :: shape = 'linear'
      character(len=8) :: transfer = 'flip'
      real(dp) :: flip_fraction = 0.99_dp
      ! &run
      real(dp) :: periods = 2.0_dp
      real(dp) :: end_time = unset
      ! &output
      character(len=1024) :: file = 'bar.h5'
      logical :: history = .true.
      integer :: snapshot_count = 0
      real(dp) :: snapshot_times(max_snapshots) = 0.0_dp
      ! &guards
      !> A run fails when its total energy exceeds this factor times the initial energy.
      real(dp) :: energy_growth_limit = 10.0_dp
      !> A run fails when a particle moves more than this many cells in one step.
      real(dp) :: max_cell_move = 1.0_dp
      ! resolved (derived) quantities, filled by resolve_config
      real(dp) :: wave_speed = 0.0_dp
      real(dp) :: dx = 0.0_dp
      real(dp) :: dt = 0.0_dp
      real(dp) :: period = 0.0_dp
      real(dp) :: final_time = 0.0_dp
      integer :: steps = 0
   end type config_t

contains

   !> The built-in default: the paper's verification case (20 elements, 1 particle per element,
   !> 10% of the critical step, USL, two periods of the first mode).
   function default_config() result(config)
      type(config_t) :: config
      config = config_t()
      call resolve_config(config)
   end function default_config

   !> The registry of the run's input: one entry per namelist variable, bound to its field of
   !> `config` (which must stay in place while the table is used). Adding a variable: a field of
   !> config_t with its default, one entry here, and the code that uses it.
   !> The order of the sweepable entries is the order of the sweep's loops (the last varies fastest).
   subroutine config_parameters(config, table)
      type(config_t), intent(inout), target :: config
      type(parameter_t), allocatable, intent(out) :: table(:)
      table = [ &
         text_entry('discretisation', 'scheme', config%scheme, 'update scheme: stress update first, last, or '// &
                    'modified last (the README gives each algorithm)', words=known_schemes, sweep_list='schemes'), &
         int_entry('discretisation', 'elements', config%elements, 'elements across the body; dx = length / elements', &
                   at_least=1, sweep_list='elements'), &
         int_entry('discretisation', 'particles_per_element', config%particles_per_element, &
                   'particles per element, evenly spaced', at_least=1, sweep_list='particles_per_element'), &
         real_entry('discretisation', 'dt_fraction', config%dt_fraction, '', 'dt = dt_fraction * dx / c, '// &
                    'c = sqrt(youngs_modulus/density)', greater_than=0.0_dp, at_most=max_dt_fraction, &
                    sweep_list='dt_fractions'), &
         text_entry('discretisation', 'shape', config%shape, 'shape functions: linear hat, uniform or '// &
                    'contiguous-particle GIMP, quadratic or cubic B-splines (README, Shape functions)', &
                    words=known_shapes, sweep_list='shapes'), &
         text_entry('discretisation', 'transfer', config%transfer, 'velocity transfer of G2P: FLIP, PIC, their '// &
                    'blend (flip_fraction), or affine PIC', words=known_transfers, sweep_list='transfers'), &
         real_entry('discretisation', 'flip_fraction', config%flip_fraction, '', "FLIP share of transfer = "// &
                    "'blend': v = f v_FLIP + (1 - f) v_PIC", at_least=0.0_dp, at_most=1.0_dp, &
                    sweep_list='flip_fractions'), &
         int_entry('discretisation', 'margin_cells', config%margin_cells, 'empty grid cells beyond each free end '// &
                   'of the body', at_least=-1, note="-1: the scene's expected motion + 2 cells"), &
         text_entry('discretisation', 'kernels', config%kernels, "'auto': the fused linear kernels where they "// &
                    "apply, else the generic path; 'generic': always the generic layered path", words='auto, generic'), &
         text_entry('scene', 'kind', config%scene_kind, 'the problem: the vibrating bar of the founding study', &
                    words='vibrating_bar', attribute='scene_kind'), &
         real_entry('scene', 'length', config%length, 'm', 'length of the bar', greater_than=0.0_dp), &
         real_entry('scene', 'youngs_modulus', config%youngs_modulus, 'Pa', "Young's modulus E", &
                    greater_than=0.0_dp, sweep_list='youngs_moduli'), &
         real_entry('scene', 'density', config%density, 'kg/m^3', 'density rho', greater_than=0.0_dp, &
                    sweep_list='densities'), &
         real_entry('scene', 'velocity_amplitude', config%velocity_amplitude, 'm/s', 'v0 of the initial velocity '// &
                    'v(x,0) = v0 sin(beta_n x), beta_n = (2n-1) pi / (2 length)', sweep_list='velocity_amplitudes'), &
         int_entry('scene', 'mode', config%mode, 'the mode n of the initial velocity', at_least=1, sweep_list='modes'), &
         real_entry('run', 'periods', config%periods, '', 'run length in periods 2 pi / omega_n of the mode '// &
                    '(give periods or end_time); steps = smallest n with n dt >= end time', greater_than=0.0_dp, &
                    optional=.true.), &
         real_entry('run', 'end_time', config%end_time, 's', 'run length in seconds (give periods or end_time)', &
                    greater_than=0.0_dp, optional=.true.), &
         text_entry('output', 'file', config%file, 'the HDF5 file written (via a temporary .part file)', &
                    attribute='output_file'), &
         logical_entry('output', 'history', config%history, 'write u_cm(t), exact u_cm(t) and energies at every step'), &
         real_list_entry('output', 'snapshot_times', config%snapshot_times, config%snapshot_count, 's', &
                         'particle and grid state at these times', at_least=0.0_dp, note='within the run'), &
         real_entry('guards', 'energy_growth_limit', config%energy_growth_limit, '', 'a run stops when its total '// &
                    'energy exceeds this factor times the initial energy', greater_than=1.0_dp), &
         real_entry('guards', 'max_cell_move', config%max_cell_move, 'cells', 'a run stops when a particle moves '// &
                    'more than this many cells in one step', greater_than=0.0_dp)]
   end subroutine config_parameters

   !> One line on each group of the run's input, for --help.
   function group_help(group) result(text)
      character(len=*), intent(in) :: group
      character(len=:), allocatable :: text
      select case (group)
      case ('scene')
         text = 'the problem and its material'
      case ('discretisation')
         text = 'grid, particles, time step and update scheme'
      case ('run')
         text = 'how long to run: periods or end_time, not both'
      case ('output')
         text = 'what is written'
      case ('guards')
         text = 'a run stops (exit 1, history kept) on NaN/Infinity, J <= 0, a particle leaving the grid, or:'
      case default
         text = ''
      end select
   end function group_help

   !> Read `path`: groups &scene, &discretisation, &run, &output, &guards, all optional.
   !> `extra_groups` names further groups another reader handles (e.g. 'sweep'),
   !> so that they are not reported as unknown. On any problem `error` lists them all.
   subroutine read_config(path, config, error, extra_groups)
      character(len=*), intent(in) :: path
      type(config_t), intent(out), target :: config
      type(error_t), allocatable, intent(out) :: error
      character(len=*), intent(in), optional :: extra_groups(:)
      type(nml_item_t), allocatable :: items(:)
      character(len=32), allocatable :: groups(:)
      integer, allocatable :: group_lines(:)
      type(parameter_t), allocatable :: table(:)
      integer :: i, periods, end_time

      config = config_t()
      ! problems of syntax do not stop the reading: every problem of the file is reported at once
      call read_namelist(path, items, groups, group_lines, error)
      do i = 1, size(groups)
         if (any(config_groups == groups(i))) cycle
         if (present(extra_groups)) then
            if (any(extra_groups == groups(i))) cycle
         end if
         call append_error(error, trim(path)//":"//str(group_lines(i))//": unknown namelist group &"// &
                           trim(groups(i))//" (known groups: "//join(config_groups)//extra_list()//")")
      end do
      call config_parameters(config, table)
      do i = 1, size(config_groups)
         call apply_items(table, items, trim(config_groups(i)), path, error)
      end do
      do i = 1, size(table)
         if (table(i)%line > 0) then
            call check_parameter(table(i), error, trim(path)//":"//str(table(i)%line)//": ")
         else
            call check_parameter(table(i), error)
         end if
      end do
      periods = find_parameter(table, 'run', 'periods')
      end_time = find_parameter(table, 'run', 'end_time')
      if (table(periods)%line > 0 .and. table(end_time)%line > 0) then
         call append_error(error, trim(path)//":"//str(table(end_time)%line)// &
                           ": run: give either periods or end_time, not both")
      else if (table(end_time)%line > 0) then
         config%periods = unset
      end if
      if (allocated(error)) return
      call validate_config(config, error)
      if (allocated(error)) return
      call resolve_config(config)
   contains
      function extra_list() result(text)
         character(len=:), allocatable :: text
         text = ''
         if (present(extra_groups)) text = ', '//join(extra_groups)
      end function extra_list
   end subroutine read_config

   !> Check every value; append one line per problem to `error`, naming the variable and range.
   !> `with_system = .false.` skips the checks against the machine (memory available, output folder),
   !> which a sweep makes once for its largest case instead of once per case.
   subroutine validate_config(config, error, with_system)
      type(config_t), intent(in) :: config
      type(error_t), allocatable, intent(inout) :: error
      logical, intent(in), optional :: with_system
      real(dp) :: c, dx, dt, end_time
      integer(i8) :: particles
      type(config_t), target :: local
      type(parameter_t), allocatable :: table(:)
      integer :: i

      local = config
      call config_parameters(local, table)
      do i = 1, size(table)
         call check_parameter(table(i), error)
      end do
      if (config%periods == unset .and. config%end_time == unset) call append_error(error, &
         "run: give periods or end_time")
      particles = int(max(config%elements, 0), i8)*int(max(config%particles_per_element, 0), i8)
      if (particles > max_count) call append_error(error, &
         "discretisation: elements*particles_per_element = "//str(particles)//" is too large; allowed: <= "// &
         str(max_count))
      if (allocated(error)) return

      ! Consistency checks that need the resolved quantities.
      c = sqrt(config%youngs_modulus/config%density)
      dx = config%length/config%elements
      dt = config%dt_fraction*dx/c
      if (.not. ieee_is_finite(c) .or. .not. ieee_is_finite(dt) .or. dt <= 0.0_dp) then
         call append_error(error, "scene: youngs_modulus/density = "//str(config%youngs_modulus/config%density)// &
                           " gives no finite positive wave speed and time step")
         return
      end if
      end_time = run_end_time(config)
      if (end_time < dt) call append_error(error, "run: end time "//str(end_time)// &
         " s is shorter than one time step dt = "//str(dt)//" s; allowed: end time >= dt")
      if (end_time/dt > real(huge(1) - 1, dp)) call append_error(error, "run: end time / dt = "// &
         str(end_time/dt)//" steps is too many; allowed: <= "//str(huge(1) - 1))
      if (config%snapshot_count > 0) then
         if (any(config%snapshot_times(1:config%snapshot_count) > end_time*(1.0_dp + 1.0e-12_dp))) &
            call append_error(error, "output: snapshot_times must lie within the run, 0 to "//str(end_time)//" s")
      end if
      if (allocated(error)) return
      if (present(with_system)) then
         if (.not. with_system) return
      end if
      call check_memory(particles, config%elements, merge(step_count(end_time, dt), 0, config%history), error)
      call check_output_path(config%file, 'output: file', error)
   end subroutine validate_config

   !> Refuse a run whose particles and grid would not fit in the memory available now.
   !> `history_steps` is the number of history entries kept (0 without history).
   subroutine check_memory(particles, elements, history_steps, error)
      integer(i8), intent(in) :: particles
      integer, intent(in) :: elements, history_steps
      type(error_t), allocatable, intent(inout) :: error
      integer(i8) :: needed, available
      integer, parameter :: bytes_per_element = 10*8 ! grid: 5 element shares + 5 nodal arrays
      integer, parameter :: bytes_per_history_entry = 5*8
      needed = particles*bytes_per_particle + int(max(elements, 0), i8)*bytes_per_element + &
               int(history_steps, i8)*bytes_per_history_entry
      available = available_memory()
      if (available > 0 .and. needed > available) call append_error(error, &
         "discretisation: elements = "//str(elements)//" and particles_per_element give "//str(particles)// &
         " particles; with "//str(history_steps)//" history steps the run needs "//str(needed/1024**2)// &
         " MiB; allowed: at most the "//str(available/1024**2)//" MiB of memory available")
   end subroutine check_memory

   !> The output file's folder must exist (the file is written there under a temporary name first).
   subroutine check_output_path(path, name, error)
      character(len=*), intent(in) :: path, name
      type(error_t), allocatable, intent(inout) :: error
      integer :: slash
      logical :: exists
      slash = index(trim(path), '/', back=.true.)
      if (slash > 1) then
         inquire (file=path(1:slash - 1)//'/.', exist=exists)
         if (.not. exists) call append_error(error, name//" = '"//trim(path)//"': folder '"//path(1:slash - 1)// &
                                             "' does not exist; allowed: a path in an existing folder")
      end if
      if (slash == len_trim(path)) call append_error(error, name//" = '"//trim(path)//"' names a folder; allowed: a file name")
   end subroutine check_output_path

   real(dp) function run_end_time(config)
      type(config_t), intent(in) :: config
      real(dp) :: omega
      if (config%end_time /= unset) then
         run_end_time = config%end_time
      else
         omega = (2*config%mode - 1)*pi/(2.0_dp*config%length)*sqrt(config%youngs_modulus/config%density)
         run_end_time = config%periods*2.0_dp*pi/omega
      end if
   end function run_end_time

   !> The time-step fraction above which `scheme` with `particles_per_element` and `shape` (default
   !> linear) is unstable. Linear: the predicted limit on fine meshes (studies/stability/
   !> linear_stability.py, 20 elements; coarser meshes allow a little more). Other shapes: the limit
   !> measured on the bar (studies/shapes/run.sh: 20 elements, 20 periods, k in steps of 0.02 and
   !> 0.05; 1, 2, 4 particles per element, 3 takes the lower of 2 and 4, more than 4 that of 4).
   !> GIMP in USF and MUSL measured as linear. linear_stability.py --shapes predicts them within 0.02
   !> (GIMP's USL limits for a bar stretched by 1e-6: the end box entering the margin cell makes a
   !> nearly empty node). Used to warn, not to refuse: studies go beyond it on purpose.
   pure real(dp) function stability_limit(scheme, particles_per_element, shape)
      character(len=*), intent(in) :: scheme
      integer, intent(in) :: particles_per_element
      character(len=*), intent(in), optional :: shape
      real(dp), parameter :: usl(8) = [0.7079_dp, 0.7568_dp, 0.7670_dp, 0.7706_dp, 0.7724_dp, 0.7733_dp, &
                                       0.7739_dp, 0.7742_dp]
      real(dp), parameter :: usf(8) = [2.0062_dp, 1.7332_dp, 1.6784_dp, 1.6601_dp, 1.6503_dp, 1.6450_dp, &
                                       1.6418_dp, 1.6398_dp]
      ! measured, ppc = 1, 2, 4
      real(dp), parameter :: usl_gimp(3) = [0.62_dp, 0.59_dp, 0.47_dp], usl_bspline2(3) = [0.62_dp, 0.89_dp, 0.92_dp], &
                             usl_bspline3(3) = [1.03_dp, 1.12_dp, 1.13_dp], usf_bspline2(3) = [2.0_dp, 2.25_dp, 2.25_dp], &
                             usf_bspline3(3) = [2.6_dp, 2.6_dp, 2.6_dp]
      character(len=8) :: kind
      integer :: k
      kind = 'linear'
      if (present(shape)) kind = shape
      k = min(max(particles_per_element, 1), 8)
      if (trim(scheme) == 'usl') then
         select case (trim(kind))
         case ('ugimp', 'cpgimp')
            stability_limit = measured(usl_gimp)
         case ('bspline2')
            stability_limit = measured(usl_bspline2)
         case ('bspline3')
            stability_limit = measured(usl_bspline3)
         case default
            stability_limit = usl(k)
         end select
      else ! USF and MUSL share their linear spectrum
         select case (trim(kind))
         case ('bspline2')
            stability_limit = measured(usf_bspline2)
         case ('bspline3')
            stability_limit = measured(usf_bspline3)
         case default
            stability_limit = usf(k)
         end select
      end if
   contains
      pure real(dp) function measured(limits)
         real(dp), intent(in) :: limits(3)
         select case (particles_per_element)
         case (:1)
            measured = limits(1)
         case (2)
            measured = limits(2)
         case (3)
            measured = min(limits(2), limits(3))
         case default
            measured = limits(3)
         end select
      end function measured
   end function stability_limit

   !> The smallest n with n*dt >= end_time, robust to round-off: a ratio within a few ulps of an
   !> integer counts as that integer (so 2 periods at 10% of dx/c give exactly 8*elements/0.1 steps).
   integer function step_count(end_time, dt)
      real(dp), intent(in) :: end_time, dt
      real(dp) :: ratio
      ratio = end_time/dt
      step_count = nint(ratio)
      if (abs(ratio - step_count) > 1.0e-9_dp*max(1.0_dp, ratio)) step_count = ceiling(ratio)
      step_count = max(step_count, 1)
   end function step_count

   !> Fill the derived quantities of a validated configuration.
   subroutine resolve_config(config)
      type(config_t), intent(inout) :: config
      real(dp) :: omega
      config%wave_speed = sqrt(config%youngs_modulus/config%density)
      config%dx = config%length/config%elements
      config%dt = config%dt_fraction*config%dx/config%wave_speed
      omega = (2*config%mode - 1)*pi/(2.0_dp*config%length)*config%wave_speed
      config%period = 2.0_dp*pi/omega
      config%final_time = run_end_time(config)
      config%steps = step_count(config%final_time, config%dt)
   end subroutine resolve_config

   !> Echo the configuration as a namelist file that reproduces the run.
   subroutine write_config_namelist(unit, config)
      integer, intent(in) :: unit
      type(config_t), intent(in) :: config
      write (unit, '(a)') config_namelist(config)
   end subroutine write_config_namelist

   !> The configuration as namelist text (one group per line) that reproduces the run.
   function config_namelist(config) result(text)
      type(config_t), intent(in) :: config
      character(len=:), allocatable :: text
      type(config_t), target :: local
      type(parameter_t), allocatable :: table(:)
      integer :: i
      local = config
      call config_parameters(local, table)
      text = ''
      do i = 1, size(config_groups)
         text = text//group_namelist(table, trim(config_groups(i)))
         if (i < size(config_groups)) text = text//new_line('a')
      end do
   end function config_namelist

   !> One line describing the run for progress and log messages.
   function config_summary(config) result(text)
      type(config_t), intent(in) :: config
      character(len=:), allocatable :: text
      text = trim(config%scheme)//", "//str(config%elements)//" elements, "//str(config%particles_per_element)// &
             " particles per element, dt = "//str(config%dt_fraction)//" dx/c = "//str(config%dt)//" s, "// &
             str(config%steps)//" steps"
   end function config_summary

   pure function join(words) result(text)
      character(len=*), intent(in) :: words(:)
      character(len=:), allocatable :: text
      integer :: i
      text = ''
      do i = 1, size(words)
         text = text//'&'//trim(words(i))
         if (i < size(words)) text = text//', '
      end do
   end function join
end module mpm_config
