!> Namelist configuration of one run: read, validate (reporting every problem), resolve derived
!> quantities (wave speed, element size, time step, step count) and echo.
!> The run's configuration as a whole: the common settings (mpm_settings) and the chosen scene's input
!> (src/scene: its own parameters, checks and resolution), read from the namelist through one parameter
!> table, validated (reporting every problem), resolved (wave speed, element size, time step, step
!> count) and echoed. It names no scene: what differs between kinds, each kind's input says.
module mpm_config
   use, intrinsic :: ieee_arithmetic, only: ieee_is_finite, ieee_is_normal, ieee_is_nan
   use mpm_kinds, only: dp, i8, pi
   use mpm_errors, only: error_t, set_error, append_error
   use mpm_strings, only: str, lower, num, num_at_least, plural
   use mpm_files, only: available_memory, path_kind, path_folder, path_other, absolute_path
   use mpm_particles, only: bytes_per_particle
   use mpm_settings, only: settings_t, max_snapshots, max_segments
   use mpm_shape, only: known_shapes, known_transfers, known_formulations
   use mpm_material, only: material_t, known_laws, law_id
   use mpm_stepper, only: known_schemes
   use mpm_implicit, only: known_integrators
   use mpm_registry, only: parameter_t, nml_item_t, text_entry, int_entry, real_entry, real_list_entry, &
                           logical_entry, for_value, used_by, parse_namelist, read_input_text, add_overrides, &
                           apply_items, check_parameter, find_parameter, group_namelist, short_number, item_place, &
                           format_value, same_value, type_real, in_list, place
   use mpm_suggest, only: did_you_mean, printable
   use mpm_scenes, only: scene_input_t, scene_kind_t, scene_slot_t, scene_catalog, scene_kinds, known_scenes, &
                         new_scene_input, default_scene
   implicit none
   private
   public :: config_t, read_config, read_config_text, input_name, validate_config, resolve_config
   public :: write_config_namelist, config_namelist
   public :: default_config, new_config, config_summary, known_schemes
   public :: max_snapshots, periodic_snapshots, max_segments, check_output_path
   public :: config_parameters, catalog_parameters, config_groups, group_help, known_scenes, scene_kind_t, scene_kinds
   public :: material_of, set_config_values
   public :: stability_limit, not_used_message, config_warnings, known_kind, other_kind_message, other_kind_list
   public :: assign_in_place
   public :: known_integrators, used_with, run_length_flags

   !> The groups of one run's input, in the order of the echo and of --help.
   character(len=16), parameter :: config_groups(*) = [character(len=16) :: 'scene', 'material', 'discretisation', &
                                                        'run', 'output', 'guards']
   !> Most snapshots snapshot_every may take over one run (each holds every particle's state).
   integer, parameter :: max_periodic_snapshots = 1000
   !> Largest number of particles or elements one run accepts (array indices are default integers).
   integer(i8), parameter :: max_count = int(huge(1), i8)
   !> Time-step fraction above which a run is refused outright (far beyond any stability limit).
   real(dp), parameter :: max_dt_fraction = 10.0_dp
   !> ... and above which an implicit run is (unconditionally stable: the step is the user's accuracy choice).
   real(dp), parameter :: max_implicit_dt_fraction = 1.0e8_dp
   !> Largest ghost penalty: its stiffness gamma E/dx only conditions the tangent worse beyond the
   !> material's (1/rcond grows as gamma); on the quasi-static column the solution's error is the same
   !> from 1e3 to 1e10, 5x it at 1e12 and 0.9 (no digit) at 1e15, where Newton still reported convergence.
   real(dp), parameter :: max_ghost_penalty = 1.0e6_dp
   !> The largest order of transfer = 'xpic' or 'fmpm' (each order one more projection per filtered velocity).
   integer, parameter :: max_transfer_order = 100

   !> Everything one run needs to know: the common settings (their defaults are the paper's Table 1 and
   !> its verification case), the scene's kind and its input (made by new_config or the reader).
   type, extends(settings_t) :: config_t
      character(len=32) :: scene_kind = default_scene
      class(scene_input_t), allocatable :: scene
   end type config_t

   !> A scene or material variable of some kind and the kinds that have it (name_kinds).
   type :: kinds_of_t
      character(len=16) :: group = ''
      character(len=32) :: name = ''
      character(len=96) :: kinds = ''
   end type kinds_of_t
   !> Every kind's scene and material variables with the kinds that have each, made by the first
   !> name_kinds (the kinds' entries are fixed): a sweep builds a table per case and per message, and
   !> asking every kind for its entries each time cost more than the rest of the table.
   type(kinds_of_t), allocatable, save :: kinds_catalog(:)

contains

   !> A configuration of scene kind `kind` (default: the default scene), every value at its default,
   !> not resolved. An unknown kind gets the default scene's input and keeps its name (validation refuses it).
   function new_config(kind) result(config)
      character(len=*), intent(in), optional :: kind
      type(config_t) :: config
      if (present(kind)) config%scene_kind = lower(trim(adjustl(kind)))
      call kind_input(config)
   end function new_config

   !> `config`'s scene input is its kind's: made at its defaults when it has none or another kind's (a
   !> program that sets scene_kind); an unknown kind keeps what it has, else gets the default scene's.
   subroutine kind_input(config)
      type(config_t), intent(inout) :: config
      class(scene_input_t), allocatable :: input
      if (allocated(config%scene)) then
         if (trim(config%scene%describe_name()) == trim(config%scene_kind)) return
      end if
      call new_scene_input(trim(config%scene_kind), input)
      if (allocated(input)) then
         call move_alloc(input, config%scene)
      else if (.not. allocated(config%scene)) then
         call new_scene_input(default_scene, config%scene)
      end if
   end subroutine kind_input

   !> The built-in default: the paper's verification case (20 elements, 1 particle per element,
   !> 10% of the critical step, USL, two periods of the first mode).
   function default_config() result(config)
      type(config_t) :: config
      config = new_config()
      call resolve_config(config)
   end function default_config

   !> The registry of the run's input: one entry per namelist variable, bound to its field of
   !> `config` (which must stay in place while the table is used): the discretisation's, the scene's kind,
   !> the scene's own (its input's entries), the law, its parameters (the scene's), the run's length, the
   !> output and the guards. Each scene entry names the kinds that have it (`kinds`, for messages and
   !> listings). Adding a common variable: a field of settings_t with its default, one entry here, and the
   !> code that uses it; a scene's: its input's entries.
   !> The order of the sweepable entries is the order of the sweep's loops (the last varies fastest).
   subroutine config_parameters(config, table)
      type(config_t), intent(inout), target :: config
      type(parameter_t), allocatable, intent(out) :: table(:)
      type(parameter_t), allocatable :: scene(:), material(:)
      call run_length_flags(config)
      call kind_input(config)
      call config%scene%entries(scene)
      call config%scene%material_entries(material)
      call name_kinds(scene)
      call name_kinds(material)
      table = [common_entries(config, 'discretisation'), common_entries(config, 'scene'), scene, &
               common_entries(config, 'material'), material, common_entries(config, 'run'), &
               common_entries(config, 'output'), common_entries(config, 'guards')]
   end subroutine config_parameters

   !> The law's note: the kinds with a law of their own when none is given ("plastic_wave: 'elastoplastic'
   !> when not given").
   function law_note() result(note)
      character(len=:), allocatable :: note
      type(scene_slot_t), allocatable :: slots(:)
      integer :: k
      note = ''
      call scene_catalog(slots)
      do k = 1, size(slots)
         if (len(slots(k)%input%default_law()) == 0) cycle
         if (len(note) > 0) note = note//'; '
         note = note//slots(k)%input%describe_name()//": '"//slots(k)%input%default_law()//"' when not given"
      end do
   end function law_note

   !> The entries of `group` that are not a scene's (the settings' and the scene's kind).
   function common_entries(config, group) result(table)
      type(config_t), intent(inout), target :: config
      character(len=*), intent(in) :: group
      type(parameter_t), allocatable :: table(:)
      select case (group)
      case ('discretisation')
         table = [ &
         text_entry('discretisation', 'scheme', config%scheme, 'update scheme: stress update first, last, or '// &
                    'modified last (docs/theory.md, Algorithm); integrator ''explicit''', words=known_schemes, &
                    sweep_list='schemes'), &
         int_entry('discretisation', 'elements', config%elements, 'elements across the body; dx = length / elements', &
                   at_least=1, sweep_list='elements'), &
         int_entry('discretisation', 'particles_per_element', config%particles_per_element, &
                   'particles per element, evenly spaced', at_least=1, sweep_list='particles_per_element'), &
         real_entry('discretisation', 'dt_fraction', config%dt_fraction, '', 'dt = dt_fraction * dx / c, '// &
                    'c = sqrt(youngs_modulus/density)', greater_than=0.0_dp, at_most=dt_fraction_limit(config), &
                    sweep_list='dt_fractions', note="integrator 'implicit': up to 1e8"), &
         text_entry('discretisation', 'shape', config%shape, 'shape functions: linear hat, uniform or '// &
                    'contiguous-particle GIMP, quadratic or cubic B-splines, or convected particle domains '// &
                    '(docs/theory.md, Shape functions; CPDI: The cures)', words=known_shapes, sweep_list='shapes'), &
         text_entry('discretisation', 'transfer', config%transfer, 'velocity transfer of G2P: FLIP, PIC, their '// &
                    'blend (flip_fraction), affine PIC, extended PIC of order xpic_order, FMPM of order fmpm_order, '// &
                    'or affine-separable FLIP (asflip_alpha; docs/theory.md, The cures)', words=known_transfers, &
                    sweep_list='transfers'), &
         for_value(real_entry('discretisation', 'flip_fraction', config%flip_fraction, '', "FLIP share of "// &
                              "transfer = 'blend': v = f v_FLIP + (1 - f) v_PIC", at_least=0.0_dp, at_most=1.0_dp, &
                              sweep_list='flip_fractions'), 'transfer', 'blend'), &
         for_value(int_entry('discretisation', 'xpic_order', config%xpic_order, "order m of transfer = 'xpic': "// &
                             "v* = sum_{k=1..m} (-1)^(k+1) C(m,k) A^(k-1) v (1: PIC)", at_least=1, &
                             at_most=max_transfer_order, sweep_list='xpic_orders'), 'transfer', 'xpic'), &
         for_value(int_entry('discretisation', 'fmpm_order', config%fmpm_order, "order k of transfer = 'fmpm': "// &
                             "v_k(q) = sum_{r<k} (I - A)^r M_L^-1 q (1: PIC)", at_least=1, &
                             at_most=max_transfer_order, sweep_list='fmpm_orders'), 'transfer', 'fmpm'), &
         for_value(real_entry('discretisation', 'asflip_alpha', config%asflip_alpha, '', "alpha of transfer = "// &
                              "'asflip': v = v_PIC + alpha (v - v_old) (0: PIC, 1: FLIP's velocity)", &
                              at_least=0.0_dp, at_most=1.0_dp, sweep_list='asflip_alphas'), 'transfer', 'asflip'), &
         text_entry('discretisation', 'formulation', config%formulation, "'updated' Lagrangian (the weights at "// &
                    "the particles' positions each step) or 'total' Lagrangian (at their reference positions, "// &
                    "once; docs/theory.md, The cures); integrator 'explicit'", words=known_formulations, &
                    sweep_list='formulations'), &
         int_entry('discretisation', 'margin_cells', config%margin_cells, 'empty grid cells beyond each free end '// &
                   'of the body', at_least=-1, note="-1: the scene's expected motion + 2 cells"), &
         text_entry('discretisation', 'kernels', config%kernels, "'auto': the fused kernels where they apply "// &
                    "(explicit runs; which scenes, shapes, transfers, laws and formulations they take: "// &
                    "docs/performance.md, Which runs take the fused kernels), else the generic path; "// &
                    "'generic': always the generic layered path", &
                    words='auto, generic'), &
         text_entry('discretisation', 'integrator', config%integrator, "time integration: 'explicit' (the "// &
                    "scheme), 'implicit' (Newmark trapezoidal rule, Newton on the grid), 'quasi_static' "// &
                    "(equilibrium in load_steps)", words=known_integrators, sweep_list='integrator'), &
         text_entry('discretisation', 'mass', config%mass, "mass matrix of integrator 'implicit': 'lumped' "// &
                    "(row sums, as the explicit schemes) or 'consistent' (sum_p m_p N_I N_J)", &
                    words='lumped, consistent', sweep_list='mass'), &
         int_entry('discretisation', 'load_steps', config%load_steps, "load increments of integrator "// &
                   "'quasi_static' (equilibrium under a fraction k/load_steps of the loads)", at_least=1, &
                   at_most=huge(1) - 1, sweep_list='load_steps'), &
         real_entry('discretisation', 'newton_tolerance', config%newton_tolerance, '', 'Newton stops at |R| <= '// &
                    'tolerance * |forces| (the sum of the magnitudes of the terms balanced at each node); '// &
                    "integrators 'implicit', 'quasi_static'", &
                    greater_than=0.0_dp, below=1.0_dp, sweep_list='newton_tolerance'), &
         int_entry('discretisation', 'max_newton_iterations', config%max_newton_iterations, 'linear solves a '// &
                   "step may take before the run stops (status newton_not_converged); integrators 'implicit', "// &
                   "'quasi_static'", at_least=1), &
         real_entry('discretisation', 'ghost_penalty', config%ghost_penalty, '', 'ghost penalty gamma on the '// &
                    'cut cells at free ends (stiffness gamma E/dx on the jump of the p-th derivative); 0: off; '// &
                    "integrators 'implicit', 'quasi_static'", &
                    at_least=-1.0_dp, at_most=max_ghost_penalty, note='-1: 0.1 for GIMP and B-splines, 0 for '// &
                    'linear; between -1 and 0 refused', sweep_list='ghost_penalty')]
      case ('scene')
         table = [text_entry('scene', 'kind', config%scene_kind, 'the problem (docs/user-guide.md, Scenes): '// &
                             scene_list(periods=.false.), words=known_scenes(), attribute='scene_kind')]
      case ('material')
         table = [text_entry('material', 'law', config%law, "constitutive law: 'hencky' sigma = E ln J (sigma += E "// &
                             "d eps), 'linear' sigma = E (J - 1), 'elastoplastic' Hencky with linear isotropic "// &
                             "hardening", words=known_laws, sweep_list='law', note=law_note())]
      case ('run')
         table = [ &
         real_entry('run', 'periods', config%periods, '', 'run length in periods of the scene ('// &
                    scene_list(periods=.true.)//'); steps = smallest n with n dt >= end time', &
                    greater_than=0.0_dp, optional=.true., given=config%periods_given), &
         real_entry('run', 'end_time', config%end_time, 's', 'run length in seconds (give periods or end_time)', &
                    greater_than=0.0_dp, optional=.true., given=config%end_time_given)]
      case ('output')
         table = [ &
         text_entry('output', 'file', config%file, 'the HDF5 file written (via a temporary .part file)', &
                    attribute='output_file'), &
         logical_entry('output', 'history', config%history, 'write u_cm(t), exact u_cm(t) and energies at every step'), &
         real_list_entry('output', 'snapshot_times', config%snapshot_times, config%snapshot_count, 's', &
                         'particle and grid state at these times', at_least=0.0_dp, note='within the run'), &
         int_entry('output', 'snapshot_every', config%snapshot_every, 'particle and grid state every N steps from '// &
                   'step 0 (evenly spaced frames; besides snapshot_times)', at_least=0, &
                   note='0: none; at most '//str(max_periodic_snapshots)//' snapshots'), &
         int_entry('output', 'checkpoint_steps', config%checkpoint_steps, 'the whole state of the run every N '// &
                   'steps, and when SIGINT, SIGTERM or SIGHUP stops it, in <file>.checkpoint (mpm1d RUN.nml '// &
                   '--restart continues from it)', at_least=0, note='0: none; a single run (a sweep''s cases none)')]
      case ('guards')
         table = [ &
         real_entry('guards', 'energy_growth_limit', config%energy_growth_limit, '', 'a run stops when its total '// &
                    'energy exceeds this factor times the initial energy', greater_than=1.0_dp), &
         real_entry('guards', 'max_cell_move', config%max_cell_move, 'cells', 'a run stops when a particle moves '// &
                    'more than this many cells in one step', greater_than=0.0_dp)]
      case default
         allocate (table(0))
      end select
   end function common_entries

   !> Each scene entry's `kinds`: the kinds whose input has a variable of its group and name (a variable
   !> given for another kind is refused naming them).
   subroutine name_kinds(table)
      type(parameter_t), intent(inout) :: table(:)
      integer :: i, j
      character(len=len(table%name)) :: name
      !$omp critical (mpm_kinds_catalog)
      if (.not. allocated(kinds_catalog)) call make_kinds_catalog()
      !$omp end critical (mpm_kinds_catalog)
      do i = 1, size(table)
         table(i)%kinds = ''
         name = lower(trim(table(i)%name))
         do j = 1, size(kinds_catalog)
            if (kinds_catalog(j)%group == table(i)%group .and. kinds_catalog(j)%name == name) then
               table(i)%kinds = kinds_catalog(j)%kinds
               exit
            end if
         end do
      end do
   end subroutine name_kinds

   !> Make kinds_catalog: each variable of a kind's entries and material entries once, its kinds named in
   !> the catalog's order, comma separated.
   subroutine make_kinds_catalog()
      type(scene_slot_t), allocatable, target :: slots(:)
      type(parameter_t), allocatable :: own(:), material(:)
      type(kinds_of_t), allocatable :: catalog(:)
      integer :: i, j, k
      call scene_catalog(slots)
      allocate (catalog(0))
      do k = 1, size(slots)
         call slots(k)%input%entries(own)
         call slots(k)%input%material_entries(material)
         own = [own, material]
         do i = 1, size(own)
            ! (a kind names a variable once, however often its entries list it)
            if (find_parameter(own(1:i - 1), trim(own(i)%group), trim(own(i)%name)) > 0) cycle
            j = catalog_place(own(i)%group, own(i)%name)
            if (j == 0) then
               catalog = [catalog, kinds_of_t(group=own(i)%group, name=own(i)%name)]
               j = size(catalog)
            end if
            if (len_trim(catalog(j)%kinds) > 0) catalog(j)%kinds = trim(catalog(j)%kinds)//', '
            catalog(j)%kinds = trim(catalog(j)%kinds)//trim(slots(k)%input%describe_name())
         end do
      end do
      call move_alloc(catalog, kinds_catalog)
   contains
      integer function catalog_place(group, name)
         character(len=*), intent(in) :: group, name
         do catalog_place = 1, size(catalog)
            if (catalog(catalog_place)%group == group .and. catalog(catalog_place)%name == name) return
         end do
         catalog_place = 0
      end function catalog_place
   end subroutine make_kinds_catalog

   !> The registry of every kind (--help, --list-parameters, the namelist reference, hints for a name in
   !> the wrong group): the entries of `config`'s settings and, in each group, every kind's entries of it
   !> (the first kind's where several have one: they share it; another kind's own default is added to its
   !> note), bound to the inputs of `slots` (made here: they and `config` must stay in place while the
   !> table is used).
   subroutine catalog_parameters(config, slots, table)
      type(config_t), intent(inout), target :: config
      type(scene_slot_t), allocatable, intent(out), target :: slots(:)
      type(parameter_t), allocatable, intent(out) :: table(:)
      type(parameter_t), allocatable :: scene(:), material(:)
      call run_length_flags(config)
      call scene_catalog(slots)
      call every_kind(scene, material)
      call name_kinds(scene)
      call name_kinds(material)
      table = [common_entries(config, 'discretisation'), common_entries(config, 'scene'), scene, &
               common_entries(config, 'material'), material, common_entries(config, 'run'), &
               common_entries(config, 'output'), common_entries(config, 'guards')]
   contains
      subroutine every_kind(scene, material)
         type(parameter_t), allocatable, intent(out) :: scene(:), material(:)
         type(parameter_t), allocatable :: own(:)
         integer :: k, i, j
         allocate (scene(0), material(0))
         do k = 1, size(slots)
            call slots(k)%input%entries(own)
            do i = 1, size(own)
               j = find_parameter(scene, 'scene', trim(own(i)%name))
               if (j == 0) then
                  scene = [scene, own(i)]
               else if (format_value(own(i)) /= format_value(scene(j))) then ! (another kind's default)
                  if (len_trim(scene(j)%note) > 0) scene(j)%note = trim(scene(j)%note)//'; '
                  scene(j)%note = trim(scene(j)%note)//slots(k)%input%describe_name()//': '// &
                                  default_text(own(i))//' when not given'
               end if
            end do
            call slots(k)%input%material_entries(own)
            do i = 1, size(own)
               if (find_parameter(material, 'material', trim(own(i)%name)) == 0) material = [material, own(i)]
            end do
         end do
      end subroutine every_kind

      !> A default as the listing shows it (a real in its shortest exact form).
      function default_text(p) result(text)
         type(parameter_t), intent(in) :: p
         character(len=:), allocatable :: text
         if (p%type == type_real) then
            text = short_number(p%real_value)
         else
            text = trim(format_value(p))
         end if
      end function default_text
   end subroutine catalog_parameters

   !> The bounds of `table` (config_parameters(config, table)) that depend on the configuration's values,
   !> set again for its present values (a table a sweep reuses for its cases): dt_fraction's upper bound
   !> (dt_fraction_limit: the integrator's).
   subroutine config_bounds(config, table)
      type(config_t), intent(in) :: config
      type(parameter_t), intent(inout) :: table(:)
      integer :: k
      k = find_parameter(table, 'discretisation', 'dt_fraction')
      table(k)%upper = dt_fraction_limit(config)
   end subroutine config_bounds

   !> The scene kinds, for the help of `kind` ("'vibrating_bar' the vibrating bar ...; ...") or, with
   !> `periods`, of `periods` ("vibrating_bar: 2 pi/omega_n ...; ...").
   function scene_list(periods) result(text)
      logical, intent(in) :: periods
      character(len=:), allocatable :: text
      type(scene_kind_t), allocatable :: kinds(:)
      integer :: k
      kinds = scene_kinds()
      text = ''
      do k = 1, size(kinds)
         if (k > 1) text = text//'; '
         if (periods) then
            text = text//trim(kinds(k)%name)//': '//trim(kinds(k)%period)
         else
            text = text//"'"//trim(kinds(k)%name)//"' "//trim(kinds(k)%what)
         end if
      end do
   end function scene_list

   !> Warnings about a valid, resolved configuration (one line each, '' when none): a run that misses
   !> what it is for (the scene's).
   function config_warnings(config) result(text)
      type(config_t), intent(in) :: config
      character(len=:), allocatable :: text
      text = config%scene%warnings(config)
   end function config_warnings

   !> A configuration filled by a program (end_time set, not read) gets the flags the reader would set.
   subroutine run_length_flags(config)
      type(config_t), intent(inout) :: config
      if (.not. ieee_is_nan(config%end_time)) config%end_time_given = .true.
      if (config%end_time_given) config%periods_given = .false.
   end subroutine run_length_flags

   !> One line on each group of the run's input, for --help.
   function group_help(group) result(text)
      character(len=*), intent(in) :: group
      character(len=:), allocatable :: text
      select case (group)
      case ('scene')
         text = 'the problem and its bodies'
      case ('material')
         text = 'the constitutive law of the bodies and its parameters'
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

   !> Read `path` ('-': standard input): groups &scene, &discretisation, &run, &output, &guards, all
   !> optional. `extra_groups` names further groups another reader handles (e.g. 'sweep'),
   !> so that they are not reported as unknown. `overrides` are command-line assignments
   !> `group.name=value` that replace the file's. On any problem `error` lists them all.
   subroutine read_config(path, config, error, extra_groups, overrides)
      character(len=*), intent(in) :: path
      type(config_t), intent(out), target :: config
      type(error_t), allocatable, intent(out) :: error
      character(len=*), intent(in), optional :: extra_groups(:), overrides(:)
      character(len=:), allocatable :: text
      config = new_config()
      call read_input_text(path, text, error)
      if (allocated(error)) return
      call read_config_text(text, input_name(path), config, error, extra_groups, overrides)
   end subroutine read_config

   !> How messages name input `path` ('-' is standard input).
   function input_name(path) result(name)
      character(len=*), intent(in) :: path
      character(len=:), allocatable :: name
      name = trim(path)
      if (name == '-') name = 'standard input'
   end function input_name

   !> read_config of namelist `text` read from `path` (named so in messages): the text read into
   !> assignments, the overrides put in, the assignments applied to the registry and checked where
   !> they were given, then the configuration validated as a whole and resolved.
   subroutine read_config_text(text, path, config, error, extra_groups, overrides)
      character(len=*), intent(in) :: text, path
      type(config_t), intent(out), target :: config
      type(error_t), allocatable, intent(out) :: error
      character(len=*), intent(in), optional :: extra_groups(:), overrides(:)
      type(nml_item_t), allocatable :: items(:)
      character(len=32), allocatable :: groups(:)
      integer, allocatable :: group_lines(:)
      type(parameter_t), allocatable :: table(:)
      character(len=16), allocatable :: known(:)
      integer :: i

      known = config_groups
      if (present(extra_groups)) known = [character(len=16) :: known, extra_groups]
      ! problems of syntax do not stop the reading: every problem of the file is reported at once
      call parse_namelist(text, path, items, groups, group_lines, error)
      call refuse_unknown_groups(groups, group_lines, known, path, error)
      if (present(overrides)) call put_overrides(items, overrides, known, error)
      ! the scene's kind first: the table has its input's variables (another kind's are refused by name)
      config = new_config(given_kind(items))
      call refuse_other_kinds(config, items, path, error)
      call config_parameters(config, table)
      do i = 1, size(config_groups)
         call apply_items(table, items, trim(config_groups(i)), path, error)
      end do
      table(find_parameter(table, 'discretisation', 'dt_fraction'))%upper = dt_fraction_limit(config)
      call check_given(table, config, error)
      call choose_run_length(table, config, error)
      ! a kind with a law of its own when none is given (the plastic wave: elastoplastic, to yield)
      if (table(find_parameter(table, 'material', 'law'))%line == 0 .and. len(config%scene%default_law()) > 0) &
         config%law = config%scene%default_law()
      call check_conditions(table, items, path, error)
      if (allocated(error)) return
      call validate_config(config, error, given=table)
      if (allocated(error)) return
      call resolve_config(config)
   end subroutine read_config_text

   !> The scene kind the items give (the last assignment of &scene kind), else the default scene.
   function given_kind(items) result(kind)
      type(nml_item_t), intent(in) :: items(:)
      character(len=:), allocatable :: kind
      integer :: i
      kind = default_scene
      do i = 1, size(items)
         if (items(i)%group /= 'scene' .or. items(i)%name /= 'kind') cycle
         if (size(items(i)%values) /= 1) cycle ! (the kind's own check reports it)
         kind = lower(trim(adjustl(items(i)%values(1)%text)))
      end do
   end function given_kind

   !> A variable of &scene or &material that `config`'s kind does not have but another kind has is refused
   !> naming the kinds it belongs to, and dropped from `items` (a name no kind has is left for the table's
   !> reader, which says so). After an unknown kind, whose own message says what the kinds are, such
   !> variables are dropped without a message of their own.
   subroutine refuse_other_kinds(config, items, path, error)
      type(config_t), intent(inout), target :: config
      type(nml_item_t), allocatable, intent(inout) :: items(:)
      character(len=*), intent(in) :: path
      type(error_t), allocatable, intent(inout) :: error
      type(parameter_t), allocatable :: table(:)
      logical, allocatable :: keep(:)
      character(len=:), allocatable :: message
      integer :: i
      logical :: known
      known = known_kind(config%scene_kind)
      call config_parameters(config, table)
      allocate (keep(size(items)))
      keep = .true.
      do i = 1, size(items)
         if (items(i)%group /= 'scene' .and. items(i)%group /= 'material') cycle
         if (find_parameter(table, trim(items(i)%group), trim(items(i)%name)) > 0) cycle
         message = other_kind_message(config, trim(items(i)%group), trim(items(i)%name))
         if (len(message) == 0) cycle
         if (known) call append_error(error, item_place(items(i), path)//message)
         keep(i) = .false.
      end do
      items = pack(items, keep)
   end subroutine refuse_other_kinds

   !> The message refusing variable `name` of `group` that `config`'s kind does not have but another kind
   !> has ("scene: 'gravity' is not used by kind = 'vibrating_bar'; it belongs to kind column"), '' when no
   !> kind has it.
   function other_kind_message(config, group, name) result(text)
      type(config_t), intent(in) :: config
      character(len=*), intent(in) :: group, name
      character(len=:), allocatable :: text
      type(config_t), target :: local
      type(scene_slot_t), allocatable, target :: slots(:)
      type(parameter_t), allocatable :: table(:)
      integer :: k
      text = ''
      local = config
      call catalog_parameters(local, slots, table)
      k = find_parameter(table, group, name)
      if (k == 0) return
      if (used_by(table(k), trim(config%scene_kind))) return
      text = not_used_message(table(k), config%scene_kind)
   end function other_kind_message

   !> What a &sweep list named `list` varies when `config`'s kind does not have it but another kind does
   !> ("scene: 'gravity' is not used by kind = 'vibrating_bar'; it belongs to kind column"), else ''
   !> (for an unknown kind the message names it; the caller, whose kind was refused already, says nothing).
   function other_kind_list(config, list) result(text)
      type(config_t), intent(in) :: config
      character(len=*), intent(in) :: list
      character(len=:), allocatable :: text
      type(config_t), target :: local
      type(scene_slot_t), allocatable, target :: slots(:)
      type(parameter_t), allocatable :: table(:)
      integer :: k
      text = ''
      local = config
      call catalog_parameters(local, slots, table)
      do k = 1, size(table)
         if (len_trim(table(k)%sweep_list) == 0) cycle
         if (table(k)%sweep_list /= list .and. (len_trim(table(k)%sweep_alias) == 0 .or. &
                                                table(k)%sweep_alias /= list)) cycle
         if (.not. used_by(table(k), trim(config%scene_kind))) text = not_used_message(table(k), config%scene_kind)
         return
      end do
   end function other_kind_list

   !> `into` (a sweep's case, made from `from`, its base) takes the settings of `from` in place: the
   !> components keep their addresses, so that a table bound to `into` (config_parameters) stays valid.
   !> The scene's input is not copied: it is the base's from the start, nothing but the table changes it,
   !> and the table sets every value a sweep's lists vary for each case.
   subroutine assign_in_place(into, from)
      type(config_t), intent(inout) :: into
      type(config_t), intent(in) :: from
      into%settings_t = from%settings_t
   end subroutine assign_in_place

   !> A group that is neither the run's nor one of `known`: named with the known group nearest to it.
   !> The list of known groups has &sweep too (an input with it is a sweep).
   subroutine refuse_unknown_groups(groups, lines, known, path, error)
      character(len=*), intent(in) :: groups(:), known(:), path
      integer, intent(in) :: lines(:)
      type(error_t), allocatable, intent(inout) :: error
      character(len=16), allocatable :: all(:)
      character(len=:), allocatable :: names, hint
      integer :: i
      all = known
      if (.not. any(all == 'sweep')) all = [character(len=16) :: all, 'sweep']
      names = join(all, ', ')
      do i = 1, size(groups)
         if (any(known == groups(i))) cycle
         hint = did_you_mean(trim(groups(i)), names, '&')
         if (len(hint) == 0) hint = ';'
         call append_error(error, trim(path)//":"//str(lines(i))//": unknown namelist group &"// &
                           printable(trim(groups(i)))//hint//" known groups: "//join(all, ', ', '&'))
      end do
   end subroutine refuse_unknown_groups

   !> Put the command-line overrides into `items`; an override of the run length (periods or end_time)
   !> replaces the input's, whichever of the two it gives.
   subroutine put_overrides(items, overrides, known, error)
      type(nml_item_t), allocatable, intent(inout) :: items(:)
      character(len=*), intent(in) :: overrides(:), known(:)
      type(error_t), allocatable, intent(inout) :: error
      type(nml_item_t), allocatable :: kept(:)
      character(len=16), allocatable :: all(:)
      integer :: i
      all = known
      if (.not. any(all == 'sweep')) all = [character(len=16) :: all, 'sweep']
      call add_overrides(items, overrides, all, error)
      if (any([(items(i)%group == 'run' .and. allocated(items(i)%origin), i=1, size(items))])) then
         allocate (kept(0))
         do i = 1, size(items)
            if (items(i)%group /= 'run' .or. allocated(items(i)%origin)) kept = [kept, items(i)]
         end do
         call move_alloc(kept, items)
      end if
   end subroutine put_overrides

   !> Each variable's range, where it was given; a variable of another integrator is refused (one of another
   !> scene kind: refuse_other_kinds; of another law: check_conditions, for_value).
   subroutine check_given(table, config, error)
      type(parameter_t), intent(in) :: table(:)
      type(config_t), intent(in) :: config
      type(error_t), allocatable, intent(inout) :: error
      integer :: i
      do i = 1, size(table)
         if (table(i)%line > 0 .and. .not. used_by_integrator(table(i)%name, config%integrator)) then
            call append_error(error, trim(table(i)%origin)//' '//integrator_message(table(i), config%integrator))
         else if (table(i)%line > 0) then
            call check_parameter(table(i), error, trim(table(i)%origin)//' ')
         else
            call check_parameter(table(i), error)
         end if
      end do
   end subroutine check_given

   !> The run's length is given by periods or by end_time, not both.
   subroutine choose_run_length(table, config, error)
      type(parameter_t), intent(in) :: table(:)
      type(config_t), intent(inout) :: config
      type(error_t), allocatable, intent(inout) :: error
      integer :: periods, end_time
      periods = find_parameter(table, 'run', 'periods')
      end_time = find_parameter(table, 'run', 'end_time')
      if (table(periods)%line > 0 .and. table(end_time)%line > 0) then
         call append_error(error, trim(table(end_time)%origin)//" run: give either periods or end_time, not both")
      else if (table(end_time)%line > 0) then
         config%periods_given = .false.
         config%periods = -huge(1.0_dp) ! no value (for programs reading config_t; the flag decides)
      else if (table(periods)%line == 0 .and. config%scene%default_periods() > 0.0_dp) then
         config%periods = config%scene%default_periods()
      end if
   end subroutine choose_run_length

   !> A variable used only with one word of another (for_value; flip_fraction, the FLIP share of
   !> transfer = 'blend') given (in its group or as a &sweep list) where no value of the other, in the
   !> run or the sweep's list of it, is that word is refused naming both, as a scene variable given to
   !> another kind is. A sweep list of several values beside other words of the other's list is refused
   !> too: each of their cases would run once per value, alike (for flip_fraction: 1 is FLIP and 0 PIC,
   !> so transfer = 'blend' alone covers them).
   subroutine check_conditions(table, items, path, error)
      type(parameter_t), intent(in) :: table(:)
      type(nml_item_t), intent(in) :: items(:)
      character(len=*), intent(in) :: path
      type(error_t), allocatable, intent(inout) :: error
      integer :: k
      do k = 1, size(table)
         if (len_trim(table(k)%needs_variable) > 0) call check_condition(k)
      end do
   contains
      subroutine check_condition(k)
         integer, intent(in) :: k
         character(len=64), allocatable :: words(:)
         character(len=:), allocatable :: where, others, named, word, need
         integer :: other, other_list, own_list, i
         other = find_parameter(table, table(k)%group, trim(table(k)%needs_variable))
         own_list = sweep_item(table(k))
         other_list = sweep_item(table(other))
         if (table(k)%line == 0 .and. own_list == 0) return
         need = trim(table(k)%needs_word)
         ! the words the run or the sweep's cases use (words the variable does not take are refused elsewhere)
         allocate (words(0))
         if (other_list > 0) then
            do i = 1, size(items(other_list)%values)
               word = lower(trim(adjustl(items(other_list)%values(i)%text)))
               if (in_list(word, trim(table(other)%words))) words = [character(len=64) :: words, word]
            end do
         else
            words = [character(len=64) :: table(other)%text_value]
         end if
         if (size(words) == 0) return
         others = ''
         do i = 1, size(words)
            if (trim(words(i)) == need .or. index(others, "'"//trim(words(i))//"'") > 0) cycle
            if (len(others) > 0) others = others//", "
            others = others//"'"//trim(words(i))//"'"
         end do
         if (own_list > 0) then
            where = item_place(items(own_list), path)//"sweep: "//trim(table(k)%name)//" (the list)"
         else
            where = trim(table(k)%origin)//" "//trim(table(k)%group)//": "//trim(table(k)%name)//" = "
            if (table(k)%type == type_real) then
               where = where//short_number(table(k)%real_value)
            else
               where = where//format_value(table(k))
            end if
         end if
         named = trim(table(other)%name)//" = "//others
         if (other_list > 0) named = "the sweep's "//trim(table(other)%name)//" list ("//others//")"
         if (.not. any(words == need)) then
            call append_error(error, where//" is used only with "//trim(table(other)%name)//" = '"//need// &
                              "', not with "//named//"; allowed: "//trim(table(k)%name)//" with "// &
                              trim(table(other)%name)//" = '"//need//"', or no "//trim(table(k)%name))
         else if (own_list > 0 .and. len(others) > 0) then
            if (size(items(own_list)%values) > 1) call append_error(error, where//" has "// &
               str(size(items(own_list)%values))//" values, but the sweep's "//trim(table(other)%name)//" "// &
               others//" does not use "//trim(table(k)%name)//": each of its cases would run once per value, "// &
               "alike; allowed: a "//trim(table(k)%name)//" list with "//trim(table(other)%name)//" = '"//need// &
               "' alone, or the other "//trim(table(other)%name)//" values in a sweep of their own")
         end if
      end subroutine check_condition

      !> The &sweep assignment of the list that varies `p` (its name or its former name), 0 if none.
      integer function sweep_item(p)
         type(parameter_t), intent(in) :: p
         integer :: i
         sweep_item = 0
         do i = 1, size(items)
            if (items(i)%group /= 'sweep' .or. len_trim(p%sweep_list) == 0) cycle
            if (items(i)%name == trim(p%sweep_list) .or. (len_trim(p%sweep_alias) > 0 .and. &
                                                          items(i)%name == trim(p%sweep_alias))) sweep_item = i
         end do
      end function sweep_item
   end subroutine check_conditions

   !> The integrators that use the variable `name`, comma separated ('' for every one): given with another
   !> integrator it is refused, as a variable of another scene kind or law is, and the echo leaves it out.
   pure function integrators_of(name) result(list)
      character(len=*), intent(in) :: name
      character(len=:), allocatable :: list
      select case (trim(name))
      case ('scheme', 'kernels', 'formulation', 'xpic_order', 'fmpm_order', 'asflip_alpha')
         list = 'explicit'
      case ('mass')
         list = 'implicit'
      case ('load_steps')
         list = 'quasi_static'
      case ('newton_tolerance', 'max_newton_iterations', 'ghost_penalty')
         list = 'implicit, quasi_static'
      case ('dt_fraction', 'transfer', 'flip_fraction', 'periods', 'end_time') ! (quasi_static has no time)
         list = 'explicit, implicit'
      case default
         list = ''
      end select
   end function integrators_of

   !> Whether `integrator` uses the variable `name` (an unknown integrator uses every one: its own check
   !> reports it).
   !> (The list once, and the common case, a variable of every integrator, without building the others:
   !> called for every variable of every case of a sweep.)
   pure logical function used_by_integrator(name, integrator)
      character(len=*), intent(in) :: name, integrator
      character(len=:), allocatable :: list
      list = integrators_of(name)
      used_by_integrator = .true.
      if (len(list) == 0) return
      if (index(', '//known_integrators//',', ', '//trim(integrator)//',') == 0) return
      used_by_integrator = index(', '//list//',', ', '//trim(integrator)//',') > 0
   end function used_by_integrator

   !> Whether a run with `law` and `integrator` uses the variable of entry `p` (a sweep's /cases has the
   !> columns of the variables some of its cases use): its integrators' (integrators_of), and of the
   !> law's variables (for_value on law, as yield_stress) those of that law.
   pure logical function used_with(p, law, integrator)
      type(parameter_t), intent(in) :: p
      character(len=*), intent(in) :: law, integrator
      used_with = used_by_integrator(p%name, integrator)
      if (trim(p%needs_variable) == 'law') used_with = used_with .and. trim(p%needs_word) == trim(law)
   end function used_with

   !> The message refusing a variable that integrator `integrator` does not use.
   function integrator_message(p, integrator) result(text)
      type(parameter_t), intent(in) :: p
      character(len=*), intent(in) :: integrator
      character(len=:), allocatable :: text
      text = trim(p%group)//": '"//trim(p%name)//"' is not used by integrator = '"//trim(integrator)// &
             "'; it belongs to integrator "//integrators_of(p%name)
   end function integrator_message

   !> The largest dt_fraction the integrator accepts: explicit 10 (far beyond any stability limit),
   !> implicit 1e8 (Newmark's trapezoidal rule is unconditionally stable).
   pure real(dp) function dt_fraction_limit(config)
      type(config_t), intent(in) :: config
      dt_fraction_limit = merge(max_implicit_dt_fraction, max_dt_fraction, trim(config%integrator) == 'implicit')
   end function dt_fraction_limit

   !> The integrator against the rest: a variable it does not use but a sweep set is refused (given in the
   !> input it is refused by name already), and the scenes it cannot run: quasi_static needs static loads
   !> and an exact static solution (the scene's static_loads; the other scenes' motion is driven by
   !> initial velocities, time-dependent forces or a driven end with the other end free, which has no
   !> equilibrium but a rigid motion). What else a scene needs of the integrator, its check says.
   !> `table` is `config`'s (validate_config's); `default_table` the defaults' (config_t()), built
   !> here when not given (a sweep builds it once for its cases).
   subroutine check_integrator(config, table, error, default_table)
      type(config_t), intent(in) :: config
      type(parameter_t), intent(in) :: table(:)
      type(error_t), allocatable, intent(inout) :: error
      type(parameter_t), intent(in), optional :: default_table(:)
      type(config_t), target :: defaults
      type(parameter_t), allocatable :: own_defaults(:)
      if (index(', '//known_integrators//',', ', '//trim(config%integrator)//',') == 0) return
      if (present(default_table)) then
         call unused_values(default_table)
      else
         defaults = new_config(config%scene_kind)
         call config_parameters(defaults, own_defaults)
         call unused_values(own_defaults)
      end if
      if (config%ghost_penalty > -1.0_dp .and. config%ghost_penalty < 0.0_dp) &
         call append_error(error, "discretisation: ghost_penalty = "//short_number(config%ghost_penalty)//"; "// &
                           "allowed: -1 (automatic: 0.1 for GIMP and B-splines, 0 for linear), or 0 to "// &
                           short_number(max_ghost_penalty)//" (0: off)")
      if (trim(config%integrator) == 'quasi_static' .and. config%end_time_given) &
         call append_error(error, integrator_message(table(find_parameter(table, 'run', 'end_time')), &
                                                     config%integrator))
      if (trim(config%integrator) == 'quasi_static' .and. .not. config%scene%static_loads()) &
         call append_error(error, "discretisation: integrator = 'quasi_static' needs a scene with static loads "// &
                           "and an exact static solution; kind = '"//trim(config%scene_kind)//"' has none "// &
                           "(its motion comes from initial velocities, time-dependent forces or a driven end); "// &
                           "allowed: kind = "//static_kinds())
   contains
      !> The kinds whose loads are static, as the message lists them ("'column'").
      function static_kinds() result(text)
         character(len=:), allocatable :: text
         type(scene_slot_t), allocatable :: slots(:)
         integer :: k
         text = ''
         call scene_catalog(slots)
         do k = 1, size(slots)
            if (.not. slots(k)%input%static_loads()) cycle
            if (len(text) > 0) text = text//' or '
            text = text//"'"//trim(slots(k)%input%describe_name())//"'"
         end do
      end function static_kinds
      !> A variable the integrator does not use whose value is not its default is refused.
      subroutine unused_values(defaults)
         type(parameter_t), intent(in) :: defaults(:)
         integer :: i
         do i = 1, size(table)
            if (same_value(table(i), defaults(i))) cycle ! (first: the cheapest test, and most values pass it)
            if (used_by_integrator(table(i)%name, config%integrator)) cycle
            if (table(i)%name == 'periods' .or. table(i)%name == 'end_time') cycle ! (flags: below)
            if (format_value(table(i)) /= format_value(defaults(i))) &
               call append_error(error, integrator_message(table(i), config%integrator))
         end do
      end subroutine unused_values
   end subroutine check_integrator


   !> The material of a validated configuration (the one body's; scenes of several materials give the
   !> parameters per particle).
   pure function material_of(config) result(material)
      type(config_t), intent(in) :: config
      type(material_t) :: material
      material = config%scene%material(config%law)
   end function material_of

   !> The message refusing a variable that scene kind `kind` does not use.
   function not_used_message(p, kind) result(text)
      type(parameter_t), intent(in) :: p
      character(len=*), intent(in) :: kind
      character(len=:), allocatable :: text
      text = trim(p%group)//": '"//trim(p%name)//"' is not used by kind = '"//trim(kind)//"'; it belongs to kind "// &
             trim(p%kinds)
   end function not_used_message

   !> Is `kind` a scene kind the code implements?
   logical function known_kind(kind)
      character(len=*), intent(in) :: kind
      known_kind = in_list(trim(kind), known_scenes())
   end function known_kind

   !> Check every value; append one line per problem to `error`, naming the variable and range, with
   !> the file and line where it was given when `given` (the table the input was read into) says.
   !> A value refused through a quantity derived from it is blamed on the variables the user typed.
   !> `with_system = .false.` skips the checks against the machine (memory available, output folder),
   !> which a sweep makes once for its largest case instead of once per case.
   !> `default_table` (optional): the table of config_t() (config_parameters), which a sweep builds once
   !> for its cases instead of once per case; `table` (optional): the table of `config` itself
   !> (config_parameters(config, table), `config` its target), which a sweep builds once and sets each
   !> case's values through, its bounds that depend on the values set here (config_bounds). Without
   !> `table` the table is built here (with the parameter tables per case, validation was 1.8 % of the
   !> paper's Table-2 sweeps).
   subroutine validate_config(config, error, with_system, given, default_table, table)
      type(config_t), intent(in) :: config
      type(error_t), allocatable, intent(inout) :: error
      logical, intent(in), optional :: with_system
      type(parameter_t), intent(in), optional :: given(:)
      type(parameter_t), intent(in), optional :: default_table(:)
      type(parameter_t), intent(inout), optional :: table(:)
      type(config_t), target :: local
      type(parameter_t), allocatable :: own_table(:)

      local = config
      call run_length_flags(local)
      if (present(table)) then
         call config_bounds(config, table)
         call validate_values(table)
      else
         call config_parameters(local, own_table)
         call validate_values(own_table)
      end if
      if (allocated(error)) return
      call config%scene%check_representable(config, error) ! (its material and motion within the doubles)
      if (allocated(error)) return
      call check_run(config, local%end_time_given, error, given)
      if (allocated(error)) return
      if (present(with_system)) then
         if (.not. with_system) return
      end if
      call check_memory(int(config%elements, i8)*config%particles_per_element, config%elements, &
                        merge(step_count(run_end_time(config), time_step(config)), 0, config%history), error, &
                        config%margin_cells, automatic_margin(config), trim(config%integrator) /= 'explicit', &
                        merge('discretisation: load_steps', 'run: its end time / dt    ', &
                              trim(config%integrator) == 'quasi_static'), &
                        config%snapshot_count + periodic_snapshots(config%snapshot_every, &
                                                                   step_count(run_end_time(config), time_step(config))))
      call check_output_path(config%file, 'output: file', error, place(given, 'output', 'file'))
   contains
      !> Each value against its range, then the checks of the values together.
      subroutine validate_values(t)
         type(parameter_t), intent(in) :: t(:)
         integer :: i
         do i = 1, size(t)
            call check_parameter(t(i), error)
         end do
         if (.not. local%periods_given .and. .not. local%end_time_given) call append_error(error, &
            "run: give periods or end_time")
         call check_counts(config, error)
         call config%scene%check(config, error, given)
         call check_integrator(config, t, error, default_table)
         call check_methods(config, error, given)
      end subroutine validate_values
   end subroutine validate_config

   !> Grid cells and particles within the integers of the arrays.
   subroutine check_counts(config, error)
      type(config_t), intent(in) :: config
      type(error_t), allocatable, intent(inout) :: error
      integer(i8) :: particles
      particles = int(max(config%elements, 0), i8)*int(max(config%particles_per_element, 0), i8)
      if (int(max(config%elements, 0), i8) + max(config%margin_cells, 0) + 8 > max_count) call append_error(error, &
         "discretisation: elements = "//str(config%elements)//" and margin_cells = "//str(config%margin_cells)// &
         " give too many grid cells; allowed: elements + margin_cells <= "//str(max_count - 8))
      if (particles > max_count) call append_error(error, &
         "discretisation: elements*particles_per_element = "//str(particles)//" is too large; allowed: <= "// &
         str(max_count))
   end subroutine check_counts

   !> The time step and the run's length: dx and dt doubles can hold, at least one step and at most
   !> huge(1) - 1 of them, what the scene needs of the run (a motion of the free ends the grid's margin can
   !> hold, a length its exact solution covers), snapshots within the run.
   subroutine check_run(config, end_time_given, error, given)
      type(config_t), intent(in) :: config
      logical, intent(in) :: end_time_given
      type(error_t), allocatable, intent(inout) :: error
      type(parameter_t), intent(in), optional :: given(:)
      real(dp) :: c, dx, dt, end_time
      c = config%scene%wave_speed()
      dx = config%scene%body_length()/config%elements
      dt = time_step(config)
      if (.not. ieee_is_normal(c) .or. .not. ieee_is_normal(dt) .or. .not. ieee_is_normal(dx) .or. dt <= 0.0_dp) then
         call append_error(error, "scene: length = "//short_number(config%scene%body_length())//" m on elements = "// &
                           str(config%elements)//" with dt_fraction = "//short_number(config%dt_fraction)// &
                           " gives dx = "//short_number(dx)//" m and dt = dt_fraction dx/c = "//short_number(dt)// &
                           " s, which doubles cannot hold; allowed: dx and dt between 2.2e-308 and 1.8e308")
         return
      end if
      end_time = run_end_time(config)
      if (end_time < dt) call append_error(error, run_too_short(config, end_time_given, end_time, dt, given))
      if (end_time/dt > real(huge(1) - 1, dp)) call append_error(error, too_many_steps(config, end_time_given, &
                                                                                         end_time, dt, given))
      ! the scene's check with the run's length in words (formatting numbers: most of a valid case's checks)
      ! only where it finds a problem
      block
         type(error_t), allocatable :: found
         call config%scene%check_run(config, end_time, dx, '', found, given)
         if (allocated(found)) call config%scene%check_run(config, end_time, dx, &
                                                           run_length(config, end_time_given, end_time, given), error, given)
      end block
      call check_snapshots(config, end_time, error, given)
      if (end_time >= dt .and. end_time/dt <= real(huge(1) - 1, dp)) &
         call check_snapshot_every(config, step_count(end_time, dt), error, given)
   end subroutine check_run

   !> The formulation, shape and transfer against each other and the integrator (docs/theory.md, The cures;
   !> against a scene: its input's check): CPDI's particles are the domains' centres, which ASFLIP's own
   !> moves are not; the implicit integrators take none of XPIC, FMPM, ASFLIP and CPDI (their Newton step
   !> moves the particles with the grid's displacement: formulation by its integrator list).
   subroutine check_methods(config, error, given)
      type(config_t), intent(in) :: config
      type(error_t), allocatable, intent(inout) :: error
      type(parameter_t), intent(in), optional :: given(:)
      logical :: new_transfer
      new_transfer = in_list(trim(config%transfer), 'xpic, fmpm, asflip')
      if (trim(config%shape) == 'cpdi' .and. trim(config%transfer) == 'asflip') &
         call append_error(error, place(given, 'discretisation', 'transfer')//"discretisation: transfer = "// &
                           "'asflip' is not used with shape = 'cpdi' (a CPDI particle is its domain's centre, moved "// &
                           "with the grid; ASFLIP moves particles off the grid's motion); allowed: another transfer, "// &
                           "or another shape")
      if (trim(config%integrator) /= 'explicit' .and. known_integrator(config%integrator)) then
         if (new_transfer) call append_error(error, place(given, 'discretisation', 'transfer')//"discretisation: "// &
                                             "transfer = '"//trim(config%transfer)//"' is not used by integrator = '"// &
                                             trim(config%integrator)//"'; allowed: transfer = 'flip', 'pic', "// &
                                             "'blend' or 'apic', or integrator = 'explicit'")
         if (trim(config%shape) == 'cpdi') call append_error(error, place(given, 'discretisation', 'shape')// &
            "discretisation: shape = 'cpdi' is not used by integrator = '"//trim(config%integrator)//"' (its "// &
            "domains' corners move with the explicit schemes' grid velocity); allowed: another shape, or "// &
            "integrator = 'explicit'")
      end if
   contains
      pure logical function known_integrator(name)
         character(len=*), intent(in) :: name
         known_integrator = in_list(trim(name), known_integrators)
      end function known_integrator
   end subroutine check_methods

   !> How the user gave the run's length: "run: end_time = 1e-3 s" or "run: periods = 2 (end time 1e-3 s)",
   !> with what the scene says of when its periods start (the impact: when the bars meet).
   function run_length(config, end_time_given, end_time, given) result(text)
      type(config_t), intent(in) :: config
      logical, intent(in) :: end_time_given
      real(dp), intent(in) :: end_time
      type(parameter_t), intent(in), optional :: given(:)
      character(len=:), allocatable :: text
      if (end_time_given) then
         text = place(given, 'run', 'end_time')//"run: end_time = "//short_number(config%end_time)//" s"
      else if (len(config%scene%start_note(end_time)) > 0) then
         text = place(given, 'run', 'periods')//"run: periods = "//short_number(config%periods)//" (end time "// &
                num(end_time, 4)//" s"//config%scene%start_note(end_time)//")"
      else
         text = place(given, 'run', 'periods')//"run: periods = "//short_number(config%periods)//" (end time "// &
                num(end_time, 4)//" s)"
      end if
   end function run_length

   !> The run is shorter than one step: name what was typed, and what would do.
   function run_too_short(config, end_time_given, end_time, dt, given) result(text)
      type(config_t), intent(in) :: config
      logical, intent(in) :: end_time_given
      real(dp), intent(in) :: end_time, dt
      type(parameter_t), intent(in), optional :: given(:)
      character(len=:), allocatable :: text
      real(dp) :: period
      if (end_time_given) then
         text = place(given, 'run', 'end_time')//"run: end_time = "//short_number(config%end_time)//" s: the end "// &
                "time is shorter than one time step dt = "//num(dt, 4)//" s; allowed: end_time >= "//num_at_least(dt, 4)// &
                " s"
         return
      end if
      period = end_time/config%periods
      text = config%scene%short_run(config, end_time, dt, given) ! (a scene's variable that makes it so)
      if (len(text) == 0) then
         text = place(given, 'run', 'periods')//"run: periods = "//short_number(config%periods)//" gives an end "// &
                "time "//num(end_time, 4)//" s, shorter than one time step dt = "//num(dt, 4)//" s; allowed: "// &
                "periods >= "//num_at_least(dt/period, 4)
      end if
   end function run_too_short

   !> The run needs more steps than the integers hold: name what was typed. In a body of several
   !> materials the step follows the fastest wave and the period the slower ones: a large contrast of
   !> wave speeds is named with the values that give it (the scene's fast_waves).
   function too_many_steps(config, end_time_given, end_time, dt, given) result(text)
      type(config_t), intent(in) :: config
      logical, intent(in) :: end_time_given
      real(dp), intent(in) :: end_time, dt
      type(parameter_t), intent(in), optional :: given(:)
      character(len=:), allocatable :: text, advice, cause, cause_advice
      text = run_length(config, end_time_given, end_time, given)//" needs "//num(end_time/dt, 4)// &
             " steps of dt = "//num(dt, 4)//" s"
      advice = "fewer periods, a larger dt_fraction or fewer elements"
      if (end_time_given) advice = "a shorter end_time, a larger dt_fraction or fewer elements"
      if (config%scene%periods_from() > 0.0_dp .and. .not. end_time_given) &
         advice = "a smaller gap or a faster approach, "//advice
      if (.not. end_time_given) then ! (the scene's wave speeds, when they are the cause)
         call config%scene%fast_waves(config, cause, cause_advice, given)
         text = cause//text
         advice = cause_advice//advice
      end if
      text = text//"; allowed: at most "//str(huge(1) - 1)//" steps ("//advice//")"
   end function too_many_steps

   !> Snapshot times within the run and in increasing order.
   subroutine check_snapshots(config, end_time, error, given)
      type(config_t), intent(in) :: config
      real(dp), intent(in) :: end_time
      type(error_t), allocatable, intent(inout) :: error
      type(parameter_t), intent(in), optional :: given(:)
      integer :: k
      if (config%snapshot_count == 0) return
      associate (t => config%snapshot_times(1:config%snapshot_count))
         do k = 1, size(t)
            if (t(k) <= end_time*(1.0_dp + 1.0e-12_dp)) cycle
            call append_error(error, place(given, 'output', 'snapshot_times')//"output: snapshot_times("//str(k)// &
                              ") = "//short_number(t(k))//" s is after the end of the run at "//num(end_time, 4)// &
                              " s; allowed: times within the run, 0 to "//num(end_time, 4)//" s")
            exit
         end do
         if (any(t(2:) < t(:size(t) - 1))) call append_error(error, place(given, 'output', 'snapshot_times')// &
            "output: snapshot_times = "//snapshot_list()//" are not in increasing order; allowed: increasing times")
      end associate
   contains
      function snapshot_list() result(text)
         character(len=:), allocatable :: text
         integer :: i
         text = ''
         do i = 1, config%snapshot_count
            if (i > 1) text = text//', '
            text = text//short_number(config%snapshot_times(i))
         end do
      end function snapshot_list
   end subroutine check_snapshots

   !> Periodic snapshots (steps 0, N, 2N, ... of the run's `steps`): at most max_periodic_snapshots.
   subroutine check_snapshot_every(config, steps, error, given)
      type(config_t), intent(in) :: config
      integer, intent(in) :: steps
      type(error_t), allocatable, intent(inout) :: error
      type(parameter_t), intent(in), optional :: given(:)
      if (config%snapshot_every <= 0) return
      if (periodic_snapshots(config%snapshot_every, steps) <= max_periodic_snapshots) return
      call append_error(error, place(given, 'output', 'snapshot_every')//"output: snapshot_every = "// &
                        str(config%snapshot_every)//" takes "//str(periodic_snapshots(config%snapshot_every, steps))// &
                        " snapshots over the run's "//plural(steps, 'step')//"; allowed: at most "// &
                        str(max_periodic_snapshots)//" snapshots, snapshot_every >= "// &
                        str(steps/max_periodic_snapshots + 1))
   end subroutine check_snapshot_every

   !> The snapshots of steps 0, every, 2 every, ... up to `steps` (0 when every = 0).
   pure integer function periodic_snapshots(every, steps)
      integer, intent(in) :: every, steps
      periodic_snapshots = 0
      if (every > 0) periodic_snapshots = steps/every + 1
   end function periodic_snapshots

   !> Refuse a run whose particles and grid would not fit in the memory available now.
   !> `history_steps` is the number of history entries kept (0 without history).
   !> `margin` (margin_cells as given, -1: automatic) adds its empty cells to the grid's.
   subroutine check_memory(particles, elements, history_steps, error, margin, automatic, implicit, history_from, &
                           snapshots)
      integer(i8), intent(in) :: particles
      integer, intent(in) :: elements, history_steps
      type(error_t), allocatable, intent(inout) :: error
      integer, intent(in), optional :: margin
      !> The cells of the scene's own margin when margin_cells = -1 (automatic_margin).
      integer(i8), intent(in), optional :: automatic
      !> the implicit integrators' workspace too (mpm_implicit: 10 doubles per particle; per node 14 arrays
      !> and the band matrices, at most 3 x 5 + 1 doubles each for the tangent and the consistent mass)
      logical, intent(in), optional :: implicit
      !> What sets the history's steps, named when the history takes most of the memory.
      character(len=*), intent(in), optional :: history_from
      !> the snapshots the run keeps (each: 9 doubles per particle, 2 per node)
      integer, intent(in), optional :: snapshots
      integer(i8) :: needed, available, margin_cells
      integer :: bytes_per_element
      integer, parameter :: bytes_per_history_entry = 5*8
      character(len=:), allocatable :: with_margin, with_snapshots
      bytes_per_element = 10*8 ! grid: 5 element shares + 5 nodal arrays
      if (present(implicit)) then
         if (implicit) bytes_per_element = bytes_per_element + (14 + 2*16)*8
      end if
      margin_cells = 0
      if (present(margin)) margin_cells = max(margin, 0)
      with_margin = ''
      if (margin_cells > 0) with_margin = " and margin_cells = "//str(margin_cells)
      if (present(automatic) .and. margin_cells == 0) then
         if (present(margin)) then
            if (margin < 0) margin_cells = automatic
         end if
         if (margin_cells > 1000) with_margin = " with the scene's automatic margin of "//str(margin_cells)//" cells"
      end if
      needed = particles*bytes_per_particle + (int(max(elements, 0), i8) + margin_cells)*bytes_per_element + &
               int(history_steps, i8)*bytes_per_history_entry
      if (present(implicit)) then
         if (implicit) needed = needed + particles*10*8
      end if
      with_snapshots = ''
      if (present(snapshots)) then
         needed = needed + int(snapshots, i8)*(particles*9*8 + (int(max(elements, 0), i8) + margin_cells)*2*8)
         if (snapshots > 0) with_snapshots = ' and '//plural(snapshots, 'snapshot')
      end if
      available = available_memory()
      if (available <= 0 .or. needed <= available) return
      if (present(history_from) .and. 2*int(history_steps, i8)*bytes_per_history_entry > needed) then
         call append_error(error, "output: history = .true. keeps "//str(history_steps)//" steps ("// &
                           trim(history_from)//" = "//str(history_steps)//") of "//str(bytes_per_history_entry)// &
                           " bytes: the run needs "//str(needed/1024**2)//" MiB; allowed: at most the "// &
                           str(available/1024**2)//" MiB of memory available (fewer steps, or history = .false.)")
      else
         call append_error(error, "discretisation: elements = "//str(elements)//with_margin//" and "// &
                           "particles_per_element give "//str(particles)//" particles; with "//str(history_steps)// &
                           " history steps"//with_snapshots//" the run needs "//str(needed/1024**2)//" MiB; allowed: "// &
                           "at most the "//str(available/1024**2)//" MiB of memory available")
      end if
   end subroutine check_memory

   !> The output file's folder must exist (the file is written there under a temporary name first). A
   !> missing folder is named with the absolute path looked for: a relative path is taken from the folder
   !> mpm1d runs in, which need not be the namelist's. `prefix`: where the file was given ("file:line: ").
   subroutine check_output_path(path, name, error, prefix)
      character(len=*), intent(in) :: path, name
      type(error_t), allocatable, intent(inout) :: error
      character(len=*), intent(in), optional :: prefix
      character(len=:), allocatable :: where, folder
      integer :: slash
      logical :: exists
      where = ''
      if (present(prefix)) where = prefix
      slash = index(trim(path), '/', back=.true.)
      if (slash > 1) then
         folder = path(1:slash - 1)
         inquire (file=folder//'/.', exist=exists)
         if (.not. exists) call append_error(error, where//name//" = '"//trim(path)//"': folder '"//folder// &
                                             "' does not exist (looked for "//absolute_path(folder)// &
                                             trim(merge(', relative to the folder mpm1d runs in', &
                                                        '                                      ', path(1:1) /= '/'))// &
                                             "); allowed: a path in an existing folder")
      end if
      if (len_trim(path) - slash > 255) then
         call append_error(error, where//name//" = '"//trim(path)//"': its last part has "//str(len_trim(path) - slash)// &
                           " characters; allowed: a file name of at most 255 characters (the file system's limit)")
      else if (slash == len_trim(path)) then
         call append_error(error, where//name//" = '"//trim(path)//"' names a folder; allowed: a file name")
      else if (path_kind(path) == path_folder) then
         call append_error(error, where//name//" = '"//trim(path)//"' is an existing folder; allowed: a file name")
      else if (path_kind(path) == path_other) then
         call append_error(error, where//name//" = '"//trim(path)//"' is not a regular file (a device, FIFO or "// &
                           "socket); allowed: a new file or a regular file to replace")
      end if
   end subroutine check_output_path

   real(dp) function run_end_time(config)
      type(config_t), intent(in) :: config
      if (trim(config%integrator) == 'quasi_static') then ! the full load
         run_end_time = 1.0_dp
      else if (config%end_time_given .or. .not. ieee_is_nan(config%end_time)) then
         run_end_time = config%end_time
      else
         run_end_time = config%scene%end_time(config) ! (periods of the scene's period, from its start)
      end if
   end function run_end_time

   !> The time step of a validated configuration: dt = dt_fraction dx/c, c the fastest wave speed; for
   !> integrator quasi_static the load increment 1/load_steps (its "time" is the load factor, 0 to 1).
   real(dp) function time_step(config)
      type(config_t), intent(in) :: config
      if (trim(config%integrator) == 'quasi_static') then
         time_step = 1.0_dp/config%load_steps
      else
         time_step = config%dt_fraction*(config%scene%body_length()/config%elements)/config%scene%wave_speed()
      end if
   end function time_step

   !> The empty cells the scene's grid gets beyond its free ends when margin_cells = -1: its reach in
   !> cells plus 2 on each free end (the scene's free_ends), as mpm_scene's margin_for counts them.
   integer(i8) function automatic_margin(config)
      type(config_t), intent(in) :: config
      real(dp) :: cells
      automatic_margin = 0
      if (config%margin_cells >= 0) return
      cells = config%scene%reach(run_end_time(config))/(config%scene%body_length()/config%elements)
      if (.not. (cells <= 1.0e9_dp)) cells = 1.0e9_dp
      automatic_margin = config%scene%free_ends()*(2 + ceiling(cells, i8))
   end function automatic_margin

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
      type(material_t) :: material
      call kind_input(config)
      config%length = config%scene%body_length()
      material = config%scene%material(config%law)
      config%youngs_modulus = material%youngs_modulus
      config%wave_speed = config%scene%wave_speed()
      config%dx = config%length/config%elements
      config%dt = time_step(config)
      config%period = config%scene%period()
      config%final_time = run_end_time(config)
      config%steps = step_count(config%final_time, config%dt)
      if (trim(config%integrator) == 'quasi_static') then
         ! the load factor runs from 0 to 1; the converged state at full load is a snapshot
         config%period = 1.0_dp
         associate (n => config%snapshot_count)
            if (n == 0) then
               n = 1
               config%snapshot_times(1) = 1.0_dp
            else if (config%snapshot_times(n) < 1.0_dp .and. n < max_snapshots) then
               n = n + 1
               config%snapshot_times(n) = 1.0_dp
            end if
         end associate
      end if
   end subroutine resolve_config

   !> Echo the configuration as a namelist file that reproduces the run.
   subroutine write_config_namelist(unit, config)
      integer, intent(in) :: unit
      type(config_t), intent(in) :: config
      write (unit, '(a)') config_namelist(config)
   end subroutine write_config_namelist

   !> The configuration as namelist text (one group per line) that reproduces the run.
   !> A variable used only with a word of another (flip_fraction with transfer = 'blend') is left out
   !> when the other has another word, unless its value is not the default: then a sweep's transfer list
   !> has the word (a validated single run could not have it), and the sweep's echo keeps the value.
   function config_namelist(config) result(text)
      type(config_t), intent(in) :: config
      character(len=:), allocatable :: text
      type(config_t), target :: local, defaults
      type(parameter_t), allocatable :: table(:), default_table(:)
      integer :: i
      local = config
      call config_parameters(local, table)
      defaults = new_config(config%scene_kind)
      call config_parameters(defaults, default_table)
      do i = 1, size(table)
         if (len_trim(table(i)%needs_variable) == 0) cycle
         if (format_value(table(i)) /= format_value(default_table(i))) table(i)%needs_variable = ''
      end do
      table = pack(table, [(used_by_integrator(table(i)%name, config%integrator), i=1, size(table))])
      text = ''
      do i = 1, size(config_groups)
         text = text//group_namelist(table, trim(config_groups(i)), trim(config%scene_kind))
         if (i < size(config_groups)) text = text//new_line('a')
      end do
   end function config_namelist

   !> One line describing the run for progress and log messages.
   function config_summary(config) result(text)
      type(config_t), intent(in) :: config
      character(len=:), allocatable :: text
      select case (trim(config%integrator))
      case ('implicit')
         text = "implicit (Newmark, "//trim(config%mass)//" mass)"
      case ('quasi_static')
         text = "quasi_static, "//plural(config%elements, "element")//", "// &
                plural(config%particles_per_element, "particle")//" per element, "// &
                plural(config%load_steps, "load step")
         return
      case default
         text = trim(config%scheme)
      end select
      text = text//", "//plural(config%elements, "element")//", "// &
             plural(config%particles_per_element, "particle")//" per element, dt = "//num(config%dt_fraction)// &
             " dx/c = "//num(config%dt, 3)//" s, "//plural(config%steps, "step")
   end function config_summary

   !> Set variables of `config` from assignments 'group.name=value', as command-line overrides give them,
   !> without validating or resolving (a program that builds a configuration: the tests, the benchmark;
   !> resolve_config after). A kind among them takes effect first: the scene's input of that kind, at its
   !> defaults, then the other values.
   subroutine set_config_values(config, assignments, error)
      type(config_t), intent(inout), target :: config
      character(len=*), intent(in) :: assignments(:)
      type(error_t), allocatable, intent(out) :: error
      type(nml_item_t), allocatable :: items(:)
      type(parameter_t), allocatable :: table(:)
      integer :: i
      allocate (items(0))
      call add_overrides(items, assignments, config_groups, error)
      if (allocated(error)) return
      do i = 1, size(items) ! (a kind given: its input first)
         if (items(i)%group == 'scene' .and. items(i)%name == 'kind') config%scene_kind = given_kind(items)
      end do
      call kind_input(config)
      call config_parameters(config, table)
      do i = 1, size(config_groups)
         call apply_items(table, items, trim(config_groups(i)), 'set_config_values', error)
      end do
      call run_length_flags(config)
   end subroutine set_config_values

   !> `words` joined by `separator`, each after `before` ('&scene, &run').
   pure function join(words, separator, before) result(text)
      character(len=*), intent(in) :: words(:), separator
      character(len=*), intent(in), optional :: before
      character(len=:), allocatable :: text
      integer :: i
      text = ''
      do i = 1, size(words)
         if (present(before)) text = text//before
         text = text//trim(words(i))
         if (i < size(words)) text = text//separator
      end do
   end function join
end module mpm_config
