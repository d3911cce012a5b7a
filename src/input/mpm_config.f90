!> Namelist configuration of one run: read, validate (reporting every problem), resolve derived
!> quantities (wave speed, element size, time step, step count) and echo.
module mpm_config
   use, intrinsic :: ieee_arithmetic, only: ieee_is_finite, ieee_is_normal, ieee_is_nan
   use mpm_kinds, only: dp, i8, pi
   use mpm_errors, only: error_t, set_error, append_error
   use mpm_strings, only: str, lower, num, plural
   use mpm_files, only: available_memory, path_kind, path_folder, path_other, absolute_path
   use mpm_particles, only: bytes_per_particle
   use mpm_shape, only: known_shapes, known_transfers, known_formulations
   use mpm_material, only: material_t, known_laws, law_id
   use mpm_registry, only: parameter_t, nml_item_t, text_entry, int_entry, real_entry, real_list_entry, &
                           logical_entry, for_kinds, for_value, used_by, parse_namelist, read_input_text, add_overrides, &
                           apply_items, check_parameter, find_parameter, group_namelist, short_number, item_place, &
                           format_value, same_value, type_real, in_list
   use mpm_suggest, only: did_you_mean, printable
   implicit none
   private
   public :: config_t, read_config, read_config_text, input_name, validate_config, resolve_config
   public :: write_config_namelist, config_namelist
   public :: default_config, config_summary, known_schemes
   public :: max_snapshots, periodic_snapshots, max_segments, check_output_path, body_length, largest_wave_speed
   public :: config_parameters, config_groups, group_help, known_scenes, scene_kind_t, scene_kinds
   public :: material_of, plastic_wave_periods
   public :: step_count, stability_limit, not_used_message, config_warnings, contact_time, known_kind
   public :: known_integrators, max_implicit_dt_fraction, used_with, run_length_flags

   !> Most snapshot times one run accepts.
   integer, parameter :: max_snapshots = 64
   !> Most snapshots snapshot_every may take over one run (each holds every particle's state).
   integer, parameter :: max_periodic_snapshots = 1000
   !> Most segments of a composite bar.
   integer, parameter :: max_segments = 16
   !> The scene kinds made of one body of one material (length, youngs_modulus, density).
   character(len=*), parameter :: single_body = 'vibrating_bar, column, manufactured, plastic_wave'
   !> Schemes the code implements.
   character(len=*), parameter :: known_schemes = 'usf, usl, musl'
   !> Scene kinds the code implements (mpm_scenes makes them).
   character(len=*), parameter :: known_scenes = 'vibrating_bar, column, manufactured, composite_bar, impact, '// &
                                                 'plastic_wave'
   !> A scene kind as --help and the help of `kind` and `periods` describe it: its name, what it is, and
   !> the period `periods` counts in it (scene_period). Every kind of known_scenes has one (test_registry).
   type :: scene_kind_t
      character(len=16) :: name = ''
      character(len=64) :: what = ''
      character(len=48) :: period = ''
   end type scene_kind_t
   type(scene_kind_t), parameter :: scene_kinds(*) = [ &
      scene_kind_t('vibrating_bar', 'the vibrating bar of the founding study', '2 pi/omega_n (its mode n)'), &
      scene_kind_t('column', 'a column under its own weight, suddenly loaded', '4L/c'), &
      scene_kind_t('manufactured', 'a manufactured solution at large strain', '2L/c'), &
      scene_kind_t('composite_bar', 'a wave through stiff-soft segments, driven at one end', &
                   'sum L_i/c_i, one crossing'), &
      scene_kind_t('impact', 'two bars colliding', '2 max L/c, from their first contact'), &
      scene_kind_t('plastic_wave', 'an elastic-plastic wave from a driven end', &
                   "L/c (the precursor's transit; default 0.8)")]
   !> The groups of one run's input, in the order of the echo and of --help.
   character(len=16), parameter :: config_groups(*) = [character(len=16) :: 'scene', 'material', 'discretisation', &
                                                        'run', 'output', 'guards']
   !> The plastic wave's run length when neither periods nor end_time is given, in precursor transit
   !> times L/c: its exact solution holds until the elastic precursor reaches the free end.
   real(dp), parameter :: plastic_wave_periods = 0.8_dp
   !> The plastic wave's drive velocity when none is given (m/s; its law is then elastoplastic): about
   !> three times the default material's yield velocity, as the materials study drives it.
   real(dp), parameter :: plastic_wave_drive = 20.0_dp
   !> Largest number of particles or elements one run accepts (array indices are default integers).
   integer(i8), parameter :: max_count = int(huge(1), i8)
   !> Largest mode: 2 mode - 1 (in beta_n) must be a default integer.
   integer, parameter :: max_mode = (huge(1) - 1)/2
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
   !> Time integrators: the explicit schemes (scheme = usf, usl, musl), Newmark's trapezoidal rule with
   !> Newton on the grid, and equilibrium in load steps (mpm_implicit).
   character(len=*), parameter :: known_integrators = 'explicit, implicit, quasi_static'

   !> Everything one run needs to know; defaults are the paper's Table 1 and its verification case.
   type :: config_t
      ! &scene
      character(len=32) :: scene_kind = 'vibrating_bar'
      real(dp) :: length = 25.0_dp
      real(dp) :: youngs_modulus = 200.0e9_dp
      real(dp) :: density = 7800.0_dp
      real(dp) :: velocity_amplitude = 0.1_dp
      integer :: mode = 1
      !> Column: gravitational acceleration g (body force -g per unit mass, towards the fixed end x = 0).
      real(dp) :: gravity = 9.81_dp
      !> Manufactured solution: displacement amplitude A (m).
      real(dp) :: amplitude = 0.025_dp
      !> Composite bar: segments left to right (length, Young's modulus, density; counts given) and the
      !> velocity the left end is driven at.
      real(dp) :: lengths(max_segments) = 0.0_dp, youngs_moduli(max_segments) = 0.0_dp, &
                  densities(max_segments) = 0.0_dp
      integer :: length_count = 0, modulus_count = 0, density_count = 0
      real(dp) :: drive_velocity = 1.0_dp
      !> Impact scene: two bars (lengths, youngs_moduli, densities above, two values each), their initial
      !> velocities, the gap between them and the contact model ('none': one shared velocity field;
      !> 'frictionless': a field per body, mpm_contact).
      real(dp) :: velocities(2) = 0.0_dp
      integer :: velocity_count = 0
      real(dp) :: gap = 0.0_dp
      character(len=16) :: contact = 'frictionless'
      ! &material (mpm_material): the law and the elastoplastic law's parameters, one body's or one per
      ! segment (composite bar) or bar (impact)
      character(len=16) :: law = 'hencky'
      real(dp) :: yield_stress = 250.0e6_dp
      real(dp) :: hardening_modulus = 10.0e9_dp
      real(dp) :: yield_stresses(max_segments) = 0.0_dp, hardening_moduli(max_segments) = 0.0_dp
      integer :: yield_count = 0, hardening_count = 0
      ! &discretisation
      !> The time integrator (explicit: the scheme; implicit, quasi_static: mpm_implicit) and what only the
      !> implicit ones use: the mass matrix (implicit), load increments (quasi_static), Newton's relative
      !> residual tolerance and iteration limit, the ghost penalty on cut cells (both).
      character(len=16) :: integrator = 'explicit'
      character(len=16) :: mass = 'lumped'
      integer :: load_steps = 10
      real(dp) :: newton_tolerance = 1.0e-10_dp
      integer :: max_newton_iterations = 25
      real(dp) :: ghost_penalty = -1.0_dp
      character(len=8) :: scheme = 'usl'
      integer :: elements = 20
      integer :: particles_per_element = 1
      real(dp) :: dt_fraction = 0.1_dp
      !> Empty grid cells beyond each free end of the body; -1: the scene's expected motion + 2 cells.
      integer :: margin_cells = -1
      !> 'auto': the fused kernels where they apply (laws hencky and linear, the updated formulation: the bar and the
      !> column with FLIP and any shape but CPDI, every scene with the linear shape and FLIP, PIC, the blend or APIC;
      !> mpm_fused's fused_choose), else the generic path; 'generic': always generic.
      character(len=8) :: kernels = 'auto'
      !> Shape functions (mpm_shape) and the velocity transfer of G2P, with the FLIP share of 'blend', the
      !> orders of 'xpic' and 'fmpm' and the alpha of 'asflip'; the formulation (updated or total Lagrangian).
      character(len=8) :: shape = 'linear'
      character(len=8) :: transfer = 'flip'
      real(dp) :: flip_fraction = 0.99_dp
      integer :: xpic_order = 2
      integer :: fmpm_order = 2
      real(dp) :: asflip_alpha = 0.99_dp
      character(len=8) :: formulation = 'updated'
      ! &run
      real(dp) :: periods = 2.0_dp
      !> NaN until set: a program that fills config_t sets end_time alone (see run_length_flags); a
      !> user's NaN is refused by its range check, as it sets end_time_given.
      real(dp) :: end_time = transfer(9221120237041090560_i8, 1.0_dp)
      !> Which of the two gives the run's length: flags of their own, set when the input gives them (no
      !> value a user can type means "not given"); end_time given makes periods_given false.
      logical :: periods_given = .true., end_time_given = .false.
      ! &output
      character(len=1024) :: file = 'bar.h5'
      logical :: history = .true.
      integer :: snapshot_count = 0
      real(dp) :: snapshot_times(max_snapshots) = 0.0_dp
      !> A snapshot every this many steps from step 0 (besides snapshot_times); 0: none.
      integer :: snapshot_every = 0
      !> The run's whole state every N steps (and when a signal stops it) in <file>.checkpoint: 0 none.
      integer :: checkpoint_steps = 0
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
      call run_length_flags(config)
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
         text_entry('discretisation', 'kernels', config%kernels, "'auto': the fused kernels where they apply (laws "// &
                    "hencky and linear, explicit, updated formulation: the bar and the column with FLIP and any shape "// &
                    "but cpdi, every scene with the linear shape and transfer flip, pic, blend or apic), "// &
                    "else the generic path; 'generic': always the generic layered path", &
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
                    'linear; between -1 and 0 refused', sweep_list='ghost_penalty'), &
         text_entry('scene', 'kind', config%scene_kind, 'the problem (docs/user-guide.md, Scenes): '// &
                    scene_list(periods=.false.), words=known_scenes, attribute='scene_kind'), &
         for_kinds(real_entry('scene', 'length', config%length, 'm', 'length of the bar', greater_than=0.0_dp), &
                   single_body), &
         for_kinds(real_entry('scene', 'youngs_modulus', config%youngs_modulus, 'Pa', "Young's modulus E", &
                              greater_than=0.0_dp, sweep_list='youngs_moduli'), single_body), &
         for_kinds(real_entry('scene', 'density', config%density, 'kg/m^3', 'density rho', greater_than=0.0_dp, &
                              sweep_list='densities'), single_body), &
         for_kinds(real_list_entry('scene', 'lengths', config%lengths, config%length_count, 'm', 'segment lengths, '// &
                                   'left (driven end) to right (free end); impact: bar 1, bar 2', greater_than=0.0_dp, &
                                   note='2 to 16 segments; impact: 2'), 'composite_bar, impact'), &
         for_kinds(real_list_entry('scene', 'youngs_moduli', config%youngs_moduli, config%modulus_count, 'Pa', &
                                   "each segment's (bar's) Young's modulus", greater_than=0.0_dp, &
                                   note='one per segment'), 'composite_bar, impact'), &
         for_kinds(real_list_entry('scene', 'densities', config%densities, config%density_count, 'kg/m^3', &
                                   "each segment's (bar's) density", greater_than=0.0_dp, note='one per segment'), &
                   'composite_bar, impact'), &
         for_kinds(real_list_entry('scene', 'velocities', config%velocities, config%velocity_count, 'm/s', &
                                   'initial velocity of bar 1 (left) and bar 2 (right)', note='two values'), 'impact'), &
         for_kinds(real_entry('scene', 'gap', config%gap, 'm', 'distance between bar 1 (on [0, L1]) and bar 2', &
                              at_least=0.0_dp, sweep_list='gaps'), 'impact'), &
         for_kinds(text_entry('scene', 'contact', config%contact, "'none': one shared velocity field (the bars "// &
                              "stick); 'frictionless': a field per bar, the centre-of-mass velocity where they "// &
                              "approach (docs/user-guide.md, impact)", words='none, frictionless', sweep_list='contacts'), &
                   'impact'), &
         for_kinds(real_entry('scene', 'drive_velocity', config%drive_velocity, 'm/s', 'velocity the left end '// &
                              'is driven at from t = 0 (pushing into the bar)', greater_than=0.0_dp, &
                              sweep_list='drive_velocities', note="plastic_wave: "//short_number(plastic_wave_drive)// &
                              " when not given"), 'composite_bar, plastic_wave'), &
         for_kinds(real_entry('scene', 'velocity_amplitude', config%velocity_amplitude, 'm/s', 'v0 of the '// &
                              'initial velocity v(x,0) = v0 sin(beta_n x), beta_n = (2n-1) pi / (2 length)', &
                              sweep_list='velocity_amplitudes'), 'vibrating_bar'), &
         for_kinds(int_entry('scene', 'mode', config%mode, 'the mode n of the initial velocity', at_least=1, &
                             at_most=max_mode, sweep_list='modes'), 'vibrating_bar'), &
         for_kinds(real_entry('scene', 'gravity', config%gravity, 'm/s^2', 'gravitational acceleration g: body '// &
                              'force -g per unit mass, towards the fixed end x = 0', greater_than=0.0_dp, &
                              sweep_list='gravities'), 'column'), &
         for_kinds(real_entry('scene', 'amplitude', config%amplitude, 'm', 'A of the manufactured displacement '// &
                              'u(X,t) = A sin(2 pi X/length) sin(pi c t/length)', greater_than=0.0_dp, &
                              note='2 pi A / length < 1', sweep_list='amplitudes'), 'manufactured'), &
         text_entry('material', 'law', config%law, "constitutive law: 'hencky' sigma = E ln J (sigma += E d eps), "// &
                    "'linear' sigma = E (J - 1), 'elastoplastic' Hencky with linear isotropic hardening", &
                    words=known_laws, sweep_list='law', note="plastic_wave: 'elastoplastic' when not given"), &
         for_kinds(for_value(real_entry('material', 'yield_stress', config%yield_stress, 'Pa', 'initial yield stress '// &
                              'sigma_y: |sigma| <= sigma_y + H alpha (law elastoplastic)', greater_than=0.0_dp, &
                              sweep_list='yield_stress'), 'law', 'elastoplastic'), 'vibrating_bar, column, plastic_wave'), &
         for_kinds(for_value(real_entry('material', 'hardening_modulus', config%hardening_modulus, 'Pa', 'linear isotropic '// &
                              'hardening modulus H (law elastoplastic; 0: perfectly plastic)', at_least=0.0_dp, &
                              sweep_list='hardening_modulus'), 'law', 'elastoplastic'), 'vibrating_bar, column, plastic_wave'), &
         for_kinds(for_value(real_list_entry('material', 'yield_stresses', config%yield_stresses, config%yield_count, 'Pa', &
                                   "each segment's (bar's) yield stress (law elastoplastic)", greater_than=0.0_dp, &
                                   note='one per segment'), 'law', 'elastoplastic'), 'composite_bar, impact'), &
         for_kinds(for_value(real_list_entry('material', 'hardening_moduli', config%hardening_moduli, config%hardening_count, &
                                   'Pa', "each segment's (bar's) hardening modulus (law elastoplastic)", &
                                   at_least=0.0_dp, note='one per segment'), 'law', 'elastoplastic'), &
                   'composite_bar, impact'), &
         real_entry('run', 'periods', config%periods, '', 'run length in periods of the scene ('// &
                    scene_list(periods=.true.)//'); steps = smallest n with n dt >= end time', &
                    greater_than=0.0_dp, optional=.true., given=config%periods_given), &
         real_entry('run', 'end_time', config%end_time, 's', 'run length in seconds (give periods or end_time)', &
                    greater_than=0.0_dp, optional=.true., given=config%end_time_given), &
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
                   '--restart continues from it)', at_least=0, note='0: none; a single run (a sweep''s cases none)'), &
         real_entry('guards', 'energy_growth_limit', config%energy_growth_limit, '', 'a run stops when its total '// &
                    'energy exceeds this factor times the initial energy', greater_than=1.0_dp), &
         real_entry('guards', 'max_cell_move', config%max_cell_move, 'cells', 'a run stops when a particle moves '// &
                    'more than this many cells in one step', greater_than=0.0_dp)]
   end subroutine config_parameters

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
      integer :: k
      text = ''
      do k = 1, size(scene_kinds)
         if (k > 1) text = text//'; '
         if (periods) then
            text = text//trim(scene_kinds(k)%name)//': '//trim(scene_kinds(k)%period)
         else
            text = text//"'"//trim(scene_kinds(k)%name)//"' "//trim(scene_kinds(k)%what)
         end if
      end do
   end function scene_list

   !> Warnings about a valid, resolved configuration (one line each, '' when none): a run that misses
   !> what it is for. An impact whose bars do not meet before the run ends (end_time given) or never
   !> meet: its error measures free flight, which any scheme follows to round-off.
   function config_warnings(config) result(text)
      type(config_t), intent(in) :: config
      character(len=:), allocatable :: text
      real(dp) :: meet
      text = ''
      if (trim(config%scene_kind) == 'plastic_wave') then
         text = plastic_wave_warning(config)
         return
      end if
      if (trim(config%scene_kind) /= 'impact') return
      meet = contact_time(config)
      if (config%velocities(1) <= config%velocities(2)) then
         text = "the bars never meet: velocities = "//short_number(config%velocities(1))//", "// &
                short_number(config%velocities(2))//" m/s (bar 1, on the left, is not faster than bar 2); the error "// &
                "measures free flight, not an impact"
      else if (meet >= config%final_time) then
         text = "the bars do not meet before the end of the run: gap = "//short_number(config%gap)//" m closing at "// &
                num(config%velocities(1) - config%velocities(2), 4)//" m/s first touches at t = "//num(meet, 4)// &
                " s, after the end time "//num(config%final_time, 4)//" s; the error measures free flight, not "// &
                "the impact (periods count from the first contact; or give a longer end_time)"
      end if
   end function config_warnings

   !> A plastic wave that cannot yield (another law than elastoplastic, or a drive at or below the yield
   !> velocity v1 = sigma_y/(rho c_e)) carries one elastic wave and no plastic front: say so ('' otherwise).
   function plastic_wave_warning(config) result(text)
      type(config_t), intent(in) :: config
      character(len=:), allocatable :: text
      real(dp) :: v1
      text = ''
      if (trim(config%law) /= 'elastoplastic') then
         text = "the plastic wave cannot yield with law = '"//trim(config%law)//"': one elastic wave, no plastic "// &
                "front (law = 'elastoplastic' makes one)"
         return
      end if
      v1 = config%yield_stress/(config%density*sqrt(config%youngs_modulus/config%density))
      if (config%drive_velocity <= v1) text = "the plastic wave cannot yield: drive_velocity = "// &
         short_number(config%drive_velocity)//" m/s is at or below the yield velocity yield_stress/(density c) = "// &
         num(v1, 4)//" m/s: one elastic wave, no plastic front (a faster drive makes one)"
   end function plastic_wave_warning

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
      config = config_t()
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

      config = config_t()
      known = config_groups
      if (present(extra_groups)) known = [character(len=16) :: known, extra_groups]
      ! problems of syntax do not stop the reading: every problem of the file is reported at once
      call parse_namelist(text, path, items, groups, group_lines, error)
      call refuse_unknown_groups(groups, group_lines, known, path, error)
      if (present(overrides)) call put_overrides(items, overrides, known, error)
      call config_parameters(config, table)
      do i = 1, size(config_groups)
         call apply_items(table, items, trim(config_groups(i)), path, error)
      end do
      table(find_parameter(table, 'discretisation', 'dt_fraction'))%upper = dt_fraction_limit(config)
      call check_given(table, config, error)
      call choose_run_length(table, config, error)
      call plastic_wave_defaults(table, config)
      call check_conditions(table, items, path, error)
      if (allocated(error)) return
      call validate_config(config, error, given=table)
      if (allocated(error)) return
      call resolve_config(config)
   end subroutine read_config_text

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

   !> Each variable's range, where it was given; a variable given for a scene kind that does not use it
   !> is refused (after an unknown kind, whose own message says what the kinds are, it is not), and so is
   !> a variable of another integrator (one of another law: check_conditions, for_value).
   subroutine check_given(table, config, error)
      type(parameter_t), intent(in) :: table(:)
      type(config_t), intent(in) :: config
      type(error_t), allocatable, intent(inout) :: error
      integer :: i
      do i = 1, size(table)
         if (table(i)%line > 0 .and. known_kind(config%scene_kind) .and. &
             .not. used_by(table(i), trim(config%scene_kind))) then
            call append_error(error, trim(table(i)%origin)//' '//not_used_message(table(i), config%scene_kind))
         else if (table(i)%line > 0 .and. .not. used_by_integrator(table(i)%name, config%integrator)) then
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
      else if (table(periods)%line == 0 .and. trim(config%scene_kind) == 'plastic_wave') then
         config%periods = plastic_wave_periods
      end if
   end subroutine choose_run_length

   !> A plastic wave that does not name its law or its drive is elastoplastic and driven at
   !> plastic_wave_drive, above the yield velocity sigma_y/(rho c_e) of the default material (6.3 m/s),
   !> so that its defaults carry the two fronts (an elastic precursor and a plastic wave).
   subroutine plastic_wave_defaults(table, config)
      type(parameter_t), intent(in) :: table(:)
      type(config_t), intent(inout) :: config
      if (trim(config%scene_kind) /= 'plastic_wave') return
      if (table(find_parameter(table, 'material', 'law'))%line == 0) config%law = 'elastoplastic'
      if (table(find_parameter(table, 'scene', 'drive_velocity'))%line == 0) config%drive_velocity = plastic_wave_drive
   end subroutine plastic_wave_defaults

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
   !> input it is refused by name already), and the scenes it cannot run. quasi_static needs static loads
   !> and an exact static solution: the column (the other scenes' motion is driven by initial velocities,
   !> time-dependent forces or a driven end with the other end free, which has no equilibrium but a rigid
   !> motion). The implicit integrators take one velocity field: the impact's frictionless contact (a
   !> velocity field per body, a non-smooth constraint) is the explicit schemes' only.
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
      if (trim(config%integrator) == 'quasi_static' .and. trim(config%scene_kind) /= 'column') &
         call append_error(error, "discretisation: integrator = 'quasi_static' needs a scene with static loads "// &
                           "and an exact static solution; kind = '"//trim(config%scene_kind)//"' has none "// &
                           "(its motion comes from initial velocities, time-dependent forces or a driven end); "// &
                           "allowed: kind = 'column'")
      if (trim(config%integrator) /= 'explicit' .and. trim(config%scene_kind) == 'impact' .and. &
          trim(config%contact) == 'frictionless') &
         call append_error(error, "scene: contact = 'frictionless' is not used by integrator = '"// &
                           trim(config%integrator)//"' (a velocity field per body, whose contact is a non-smooth "// &
                           "constraint the Newton iteration does not take); allowed: contact = 'none', or "// &
                           "integrator = 'explicit'")
   contains
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
      material%law = law_id(config%law)
      material%youngs_modulus = config%youngs_modulus
      if (trim(config%law) == 'elastoplastic') then
         material%yield_stress = config%yield_stress
         material%hardening_modulus = config%hardening_modulus
      end if
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
   pure logical function known_kind(kind)
      character(len=*), intent(in) :: kind
      known_kind = in_list(trim(kind), known_scenes)
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
      call check_representable(config, error)
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
         call check_scene(config, error, given)
         call check_material(config, error)
         call check_integrator(config, t, error, default_table)
         call check_methods(config, error, given)
      end subroutine validate_values
   end subroutine validate_config

   !> Where variable `name` of `group` was given ("file:line: "), '' when `given` does not say.
   function place(given, group, name) result(prefix)
      type(parameter_t), intent(in), optional :: given(:)
      character(len=*), intent(in) :: group, name
      character(len=:), allocatable :: prefix
      integer :: k
      prefix = ''
      if (.not. present(given)) return
      k = find_parameter(given, group, name)
      if (k == 0) return
      if (given(k)%line > 0) prefix = trim(given(k)%origin)//' '
   end function place

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

   !> What a scene needs of its variables together (each variable's range is checked on its own).
   subroutine check_scene(config, error, given)
      type(config_t), intent(in) :: config
      type(error_t), allocatable, intent(inout) :: error
      type(parameter_t), intent(in), optional :: given(:)
      select case (trim(config%scene_kind))
      case ('manufactured')
         if (2*pi*config%amplitude >= config%length) call append_error(error, place(given, 'scene', 'amplitude')// &
            "scene: kind = 'manufactured' needs 2 pi amplitude / length < 1 (F > 0 everywhere); amplitude = "// &
            short_number(config%amplitude)//" m, length = "//short_number(config%length)//" m give "// &
            num(2*pi*config%amplitude/config%length, 4)//"; allowed: amplitude < "//num(config%length/(2*pi), 4)//" m")
      case ('composite_bar')
         if (config%length_count < 2 .or. config%modulus_count /= config%length_count .or. &
             config%density_count /= config%length_count) call append_error(error, place(given, 'scene', 'lengths')// &
            "scene: kind = 'composite_bar' needs 2 to "//str(max_segments)//" segments: lengths, youngs_moduli and "// &
            "densities with one value each (given "//str(config%length_count)//", "//str(config%modulus_count)// &
            ", "//str(config%density_count)//")")
      case ('impact')
         call check_impact(config, error, given)
      end select
   end subroutine check_scene

   !> The impact's two bars: two values of each list, the configurations its exact solution covers
   !> (mpm_scene_impact): equal impedances rho c, and for contact = 'none' (the bars stick) equal wave
   !> transit times L/c; and a grid that resolves both bars: `elements` spans both bars and the gap, and
   !> a bar shorter than half a cell would get a cell of its own it does not fill.
   subroutine check_impact(config, error, given)
      type(config_t), intent(in) :: config
      type(error_t), allocatable, intent(inout) :: error
      type(parameter_t), intent(in), optional :: given(:)
      real(dp) :: z(2), transit(2), dx, shortest
      integer :: b
      if (config%length_count /= 2 .or. config%modulus_count /= 2 .or. config%density_count /= 2 .or. &
          config%velocity_count /= 2) then
         call append_error(error, place(given, 'scene', 'lengths')//"scene: kind = 'impact' needs two bars: "// &
                           "lengths, youngs_moduli, densities and velocities with two values each (given "// &
                           str(config%length_count)//", "//str(config%modulus_count)//", "// &
                           str(config%density_count)//", "//str(config%velocity_count)//")")
         return
      end if
      z = sqrt(config%youngs_moduli(1:2)*config%densities(1:2))
      transit = config%lengths(1:2)/sqrt(config%youngs_moduli(1:2)/config%densities(1:2))
      if (abs(z(1) - z(2)) > 1.0e-9_dp*maxval(z)) call append_error(error, place(given, 'scene', 'youngs_moduli')// &
         "scene: kind = 'impact' needs equal impedances sqrt(youngs_moduli*densities) of the two bars (its exact "// &
         "solution covers those); given "//num(z(1), 6)//" and "//num(z(2), 6)//" kg/(m^2 s)")
      if (trim(config%contact) == 'none' .and. abs(transit(1) - transit(2)) > 1.0e-9_dp*maxval(transit)) &
         call append_error(error, place(given, 'scene', 'contact')//"scene: kind = 'impact' with contact = 'none' "// &
                           "needs equal wave transit times lengths/c of the two bars (the stuck bars' exact "// &
                           "solution); given "//num(transit(1), 6)//" and "//num(transit(2), 6)//" s")
      dx = body_length(config)/config%elements
      shortest = minval(config%lengths(1:2))
      b = minloc(config%lengths(1:2), 1)
      if (shortest < 0.5_dp*dx) then
         call append_error(error, place(given, 'scene', 'gap')//"scene: gap = "//short_number(config%gap)// &
                           " m with lengths = "//short_number(config%lengths(1))//", "// &
                           short_number(config%lengths(2))//" m on elements = "//str(config%elements)//" gives "// &
                           "cells of dx = (lengths(1) + gap + lengths(2))/elements = "//num(dx, 4)//" m, more than "// &
                           "twice bar "//str(b)//"'s length: the grid cannot resolve it; allowed: dx <= 2 "// &
                           "lengths("//str(b)//"), that is gap <= "//num(max(0.0_dp, 2*shortest*config%elements - &
                           sum(config%lengths(1:2))), 4)//" m at elements = "//str(config%elements)// &
                           " (or elements >= "//num(body_length(config)/(2*shortest), 4)//")")
      end if
   end subroutine check_impact

   !> The time step and the run's length: dx and dt doubles can hold, at least one step and at most
   !> huge(1) - 1 of them, a motion of the free ends the grid's margin can hold, snapshots within the run.
   subroutine check_run(config, end_time_given, error, given)
      type(config_t), intent(in) :: config
      logical, intent(in) :: end_time_given
      type(error_t), allocatable, intent(inout) :: error
      type(parameter_t), intent(in), optional :: given(:)
      real(dp) :: c, dx, dt, end_time
      c = largest_wave_speed(config)
      dx = body_length(config)/config%elements
      dt = time_step(config)
      if (.not. ieee_is_normal(c) .or. .not. ieee_is_normal(dt) .or. .not. ieee_is_normal(dx) .or. dt <= 0.0_dp) then
         call append_error(error, "scene: length = "//short_number(body_length(config))//" m on elements = "// &
                           str(config%elements)//" with dt_fraction = "//short_number(config%dt_fraction)// &
                           " gives dx = "//short_number(dx)//" m and dt = dt_fraction dx/c = "//short_number(dt)// &
                           " s, which doubles cannot hold; allowed: dx and dt between 2.2e-308 and 1.8e308")
         return
      end if
      end_time = run_end_time(config)
      if (end_time < dt) call append_error(error, run_too_short(config, end_time_given, end_time, dt, given))
      if (end_time/dt > real(huge(1) - 1, dp)) call append_error(error, too_many_steps(config, end_time_given, &
                                                                                         end_time, dt, given))
      if (trim(config%scene_kind) == 'plastic_wave' .and. end_time > (1.0_dp + 1.0e-12_dp)*config%length/c) &
         call append_error(error, run_length(config, end_time_given, end_time, given)//" ends after the elastic "// &
                           "precursor reaches the free end at L/c = "//num(config%length/c, 4)//" s, where the "// &
                           "plastic wave's exact solution stops holding; allowed: periods <= 1 (end_time <= "// &
                           num(config%length/c, 4)//" s)")
      call check_motion(config, end_time, dx, error, given)
      call check_snapshots(config, end_time, error, given)
      if (end_time >= dt .and. end_time/dt <= real(huge(1) - 1, dp)) &
         call check_snapshot_every(config, step_count(end_time, dt), error, given)
   end subroutine check_run

   !> The formulation, shape and transfer against the scene and the integrator (docs/theory.md, The cures):
   !> the total-Lagrangian formulation keeps the reference configuration, which the impact's contact cannot
   !> use; CPDI's domains are one body's chain of corners and its particles the domains' centres, which
   !> ASFLIP's own moves and the impact's bars are not; XPIC, FMPM and ASFLIP keep grid fields of one
   !> velocity field, not the impact's field per bar; the implicit integrators take none of them (their
   !> Newton step moves the particles with the grid's displacement: formulation by its integrator list).
   subroutine check_methods(config, error, given)
      type(config_t), intent(in) :: config
      type(error_t), allocatable, intent(inout) :: error
      type(parameter_t), intent(in), optional :: given(:)
      logical :: new_transfer
      new_transfer = in_list(trim(config%transfer), 'xpic, fmpm, asflip')
      if (trim(config%formulation) == 'total' .and. trim(config%scene_kind) == 'impact') &
         call append_error(error, place(given, 'discretisation', 'formulation')//"discretisation: formulation = "// &
                           "'total' is not used by kind = 'impact' (the bars' contact needs their current "// &
                           "configuration; the total-Lagrangian formulation keeps the reference one); allowed: "// &
                           "formulation = 'updated', or another kind")
      if (trim(config%shape) == 'cpdi' .and. trim(config%scene_kind) == 'impact') &
         call append_error(error, place(given, 'discretisation', 'shape')//"discretisation: shape = 'cpdi' is not "// &
                           "used by kind = 'impact' (the bars' domains and their contact are not implemented for "// &
                           "CPDI); allowed: another shape, or another kind")
      if (trim(config%shape) == 'cpdi' .and. trim(config%transfer) == 'asflip') &
         call append_error(error, place(given, 'discretisation', 'transfer')//"discretisation: transfer = "// &
                           "'asflip' is not used with shape = 'cpdi' (a CPDI particle is its domain's centre, moved "// &
                           "with the grid; ASFLIP moves particles off the grid's motion); allowed: another transfer, "// &
                           "or another shape")
      if (new_transfer .and. trim(config%scene_kind) == 'impact' .and. trim(config%contact) == 'frictionless') &
         call append_error(error, place(given, 'discretisation', 'transfer')//"discretisation: transfer = '"// &
                           trim(config%transfer)//"' is not used with contact = 'frictionless' (its grid fields "// &
                           "are of one velocity field, not of a field per bar); allowed: contact = 'none', or "// &
                           "transfer = 'flip', 'pic', 'blend' or 'apic'")
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

   !> The &material group against the scene (a variable of another law is refused by its entry's
   !> condition, for_value): an elastoplastic composite bar or impact needs yield_stresses and hardening_moduli with one
   !> value per segment, and the manufactured solution's body force is made for an elastic law.
   subroutine check_material(config, error)
      type(config_t), intent(in) :: config
      type(error_t), allocatable, intent(inout) :: error
      logical :: several
      several = trim(config%scene_kind) == 'composite_bar' .or. trim(config%scene_kind) == 'impact'
      if (trim(config%law) == 'elastoplastic' .and. several .and. (config%yield_count /= config%length_count .or. &
                              config%hardening_count /= config%length_count)) then
         call append_error(error, "material: law = 'elastoplastic' with kind = '"//trim(config%scene_kind)// &
                           "' needs yield_stresses and hardening_moduli with one value per segment (given "// &
                           str(config%yield_count)//" and "//str(config%hardening_count)//" for "// &
                           str(config%length_count)//" segments)")
      end if
      if (trim(config%scene_kind) == 'manufactured' .and. trim(config%law) == 'elastoplastic') &
         call append_error(error, "material: law = 'elastoplastic' is not used by kind = 'manufactured' (its body "// &
                           "force makes the motion exact for an elastic law); allowed: law = 'hencky' or 'linear'")
      ! the column's weight at its fixed end, rho g L: a perfectly plastic column yielding there has no
      ! equilibrium (docs/theory.md, The static column): it flows without bound (a quasi-static run left
      ! the grid at x = 3.5e10 m, an explicit one tripped the energy guard)
      if (trim(config%scene_kind) == 'column' .and. trim(config%law) == 'elastoplastic' .and. &
          config%hardening_modulus == 0.0_dp) then
         if (config%yield_stress < config%density*config%gravity*config%length) &
            call append_error(error, "material: hardening_modulus = 0 (perfectly plastic) with yield_stress = "// &
                              short_number(config%yield_stress)//" Pa, below the column's weight at its fixed end "// &
                              "rho g L = "//num(config%density*config%gravity*config%length, 4)//" Pa: the column "// &
                              "yields and has no equilibrium; allowed: yield_stress >= "// &
                              num(config%density*config%gravity*config%length, 4)//" Pa, or hardening_modulus > 0")
      end if
   end subroutine check_material

   !> How the user gave the run's length: "run: end_time = 1e-3 s" or "run: periods = 2 (end time 1e-3 s)",
   !> for the impact with the time the bars meet, from which periods count.
   function run_length(config, end_time_given, end_time, given) result(text)
      type(config_t), intent(in) :: config
      logical, intent(in) :: end_time_given
      real(dp), intent(in) :: end_time
      type(parameter_t), intent(in), optional :: given(:)
      character(len=:), allocatable :: text
      if (end_time_given) then
         text = place(given, 'run', 'end_time')//"run: end_time = "//short_number(config%end_time)//" s"
      else if (contact_time(config) > 0.0_dp) then
         text = place(given, 'run', 'periods')//"run: periods = "//short_number(config%periods)//" (end time "// &
                num(end_time, 4)//" s: the bars meet at t = gap/(velocities(1) - velocities(2)) = "// &
                num(contact_time(config), 4)//" s with gap = "//short_number(config%gap)//" m, and periods count "// &
                "from then)"
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
      integer(i8) :: largest_mode
      if (end_time_given) then
         text = place(given, 'run', 'end_time')//"run: end_time = "//short_number(config%end_time)//" s: the end "// &
                "time is shorter than one time step dt = "//num(dt, 4)//" s; allowed: end_time >= "//num(dt, 4)//" s"
         return
      end if
      period = end_time/config%periods
      if (trim(config%scene_kind) == 'vibrating_bar' .and. config%mode > 1) then
         ! periods (2 pi/omega_n = 4 L/((2n-1) c)) >= dt  <=>  2n - 1 <= periods 4 L/(c dt)
         largest_mode = int(min((config%periods*4*config%length/(largest_wave_speed(config)*dt) + 1)/2, &
                                real(huge(1), dp)), i8)
         text = place(given, 'scene', 'mode')//"scene: mode = "//str(config%mode)//" with periods = "// &
                short_number(config%periods)//" gives an end time "//num(end_time, 4)//" s, shorter than one "// &
                "time step dt = "//num(dt, 4)//" s; allowed: mode <= "//str(largest_mode)//" (or run: periods >= "// &
                num(dt/period, 4)//")"
      else
         text = place(given, 'run', 'periods')//"run: periods = "//short_number(config%periods)//" gives an end "// &
                "time "//num(end_time, 4)//" s, shorter than one time step dt = "//num(dt, 4)//" s; allowed: "// &
                "periods >= "//num(dt/period, 4)
      end if
   end function run_too_short

   !> The run needs more steps than the integers hold: name what was typed. In a body of several
   !> materials the step follows the fastest wave and the period the slower ones: a large contrast of
   !> wave speeds is named with the values that give it.
   function too_many_steps(config, end_time_given, end_time, dt, given) result(text)
      type(config_t), intent(in) :: config
      logical, intent(in) :: end_time_given
      real(dp), intent(in) :: end_time, dt
      type(parameter_t), intent(in), optional :: given(:)
      character(len=:), allocatable :: text, advice, part
      real(dp), allocatable :: c(:)
      integer :: fast, slow
      text = run_length(config, end_time_given, end_time, given)//" needs "//num(end_time/dt, 4)// &
             " steps of dt = "//num(dt, 4)//" s"
      advice = "fewer periods, a larger dt_fraction or fewer elements"
      if (end_time_given) advice = "a shorter end_time, a larger dt_fraction or fewer elements"
      if (contact_time(config) > 0.0_dp .and. .not. end_time_given) advice = "a smaller gap or a faster approach, "//advice
      if (trim(config%scene_kind) == 'composite_bar' .or. trim(config%scene_kind) == 'impact') then
         c = sqrt(config%youngs_moduli(1:config%length_count)/config%densities(1:config%length_count))
         fast = maxloc(c, 1)
         slow = minloc(c, 1)
         if (c(fast) > 100*c(slow) .and. .not. end_time_given) then
            part = merge('segment', 'bar    ', trim(config%scene_kind) == 'composite_bar')
            text = place(given, 'scene', 'youngs_moduli')//"scene: youngs_moduli("//str(fast)//") = "// &
                   short_number(config%youngs_moduli(fast))//" Pa and densities("//str(fast)//") = "// &
                   short_number(config%densities(fast))//" kg/m^3 give "//trim(part)//" "//str(fast)//" a wave "// &
                   "speed of "//num(c(fast), 4)//" m/s, "//num(c(fast)/c(slow), 3)//" times "//trim(part)//" "// &
                   str(slow)//"'s ("//num(c(slow), 4)//" m/s): dt follows the fastest wave, the period the "// &
                   "slower ones, so "//text
            advice = "wave speeds sqrt(youngs_moduli/densities) closer together, "//advice
         end if
      end if
      text = text//"; allowed: at most "//str(huge(1) - 1)//" steps ("//advice//")"
   end function too_many_steps

   !> A free end's motion over the run must fit the grid's automatic margin (margin_cells = -1): at most
   !> 1e8 cells, as for the vibrating bar (check_representable). The composite bar's driven end and the
   !> impact's bars are named here (their motion grows with the run's length).
   subroutine check_motion(config, end_time, dx, error, given)
      type(config_t), intent(in) :: config
      real(dp), intent(in) :: end_time, dx
      type(error_t), allocatable, intent(inout) :: error
      type(parameter_t), intent(in), optional :: given(:)
      real(dp), parameter :: most_cells = 1.0e8_dp
      real(dp) :: cells
      if (config%margin_cells >= 0) return
      cells = free_end_reach(config, end_time)/dx
      if (.not. (cells > most_cells)) return
      select case (trim(config%scene_kind))
      case ('composite_bar')
         call append_error(error, place(given, 'scene', 'drive_velocity')//"scene: drive_velocity = "// &
                           short_number(config%drive_velocity)//" m/s moves the bar's free end by up to 4 v T = "// &
                           num(free_end_reach(config, end_time), 4)//" m over the run (T = "//num(end_time, 4)// &
                           " s), about "//num(cells, 3)//" cells of dx = "//num(dx, 4)//" m for the grid's margin"// &
                           " to hold; allowed: at most 1e8 cells, drive_velocity <= "// &
                           num(config%drive_velocity*most_cells/cells, 4)//" m/s")
      case ('impact')
         call append_error(error, place(given, 'scene', 'velocities')//"scene: velocities = "// &
                           short_number(config%velocities(1))//", "//short_number(config%velocities(2))// &
                           " m/s move the bars' outer ends by up to 1.5 max |v| T = "// &
                           num(free_end_reach(config, end_time), 4)//" m over the run (T = "//num(end_time, 4)// &
                           " s), about "//num(cells, 3)//" cells of dx = "//num(dx, 4)//" m for the grid's margins"// &
                           " to hold; allowed: at most 1e8 cells, |velocities| <= "// &
                           num(maxval(abs(config%velocities))*most_cells/cells, 4)//" m/s")
      end select
   end subroutine check_motion

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

   !> Refuse a body whose material or motion doubles cannot represent, naming the variables typed: the
   !> wave speed (E/rho), and for the vibrating bar the free end's motion in cells (the grid's margin
   !> must hold it: at most 1e8 cells), its displacements (normal doubles), the energy rho v0^2 L/4 and
   !> the stress amplitude sqrt(E rho) |v0| (finite doubles). |v0| >= c is allowed (studies/stability
   !> runs v0 = c on purpose; the guards stop such a run).
   !> Magnitudes are compared as logarithms so that the check itself cannot overflow.
   subroutine check_representable(config, error)
      type(config_t), intent(in) :: config
      type(error_t), allocatable, intent(inout) :: error
      real(dp), parameter :: top = log10(huge(1.0_dp)), bottom = log10(tiny(1.0_dp))
      real(dp) :: log_ratio, log_c, log_v, log_cells
      integer :: k
      character(len=:), allocatable :: extra
      extra = ''
      if (trim(config%scene_kind) == 'composite_bar') then
         do k = 1, config%length_count
            log_ratio = log10(config%youngs_moduli(k)) - log10(config%densities(k))
            if (log_ratio > top .or. log_ratio < bottom) call append_error(error, "scene: youngs_moduli("// &
               str(k)//") = "//short_number(config%youngs_moduli(k))//" Pa and densities("//str(k)//") = "// &
               short_number(config%densities(k))//" kg/m^3 give E/rho = 1e"//str(nint(log_ratio))// &
               ", beyond the doubles; allowed: 2.2e-308 <= youngs_moduli/densities <= 1.8e308")
         end do
         return
      end if
      log_ratio = log10(config%youngs_modulus) - log10(config%density)
      if (log_ratio > top .or. log_ratio < bottom) then
         call append_error(error, "scene: "//material()//" give no wave speed sqrt(E/rho) doubles can hold "// &
                           "(E/rho = 1e"//str(nint(log_ratio))//"); allowed: 2.2e-308 <= youngs_modulus/density <= 1.8e308")
         return
      end if
      if (trim(config%scene_kind) == 'column') then
         ! strain at the fixed end rho g L/E = g L/c^2 (>= 1: J <= 0)
         log_v = log10(config%gravity) + log10(config%length) - log_ratio
         if (log_v >= 0.0_dp) then
            call append_error(error, "scene: gravity = "//short_number(config%gravity)//" m/s^2, length = "// &
                              short_number(config%length)//" m and "//material()//" give a strain g L rho/E = 1e"// &
                              str(nint(log_v))//" at the fixed end; allowed: gravity length density/youngs_modulus < 1")
            return
         end if
         ! the column's exact solution and energies use these products as they stand
         extra = ", gravity = "//short_number(config%gravity)//" m/s^2"
         call within("the sag g L^2/c^2", log_v + log10(config%length))
         call within("g L", log10(config%gravity) + log10(config%length))
         call within("L^3", 3*log10(config%length))
         call within("g^2", 2*log10(config%gravity))
         call within("the energy rho g^2 L^3/c^2", log10(config%density) + 2*log10(config%gravity) + &
                     3*log10(config%length) - log_ratio)
         return
      end if
      if (trim(config%scene_kind) == 'manufactured') then
         ! the manufactured solution's body force, energies and error measure use these products as they stand
         extra = ", amplitude = "//short_number(config%amplitude)//" m"
         call within("(c/L)^2", log_ratio - 2*log10(config%length))
         call within("the body force A (c/L)^2", log10(config%amplitude) + log_ratio - 2*log10(config%length))
         call within("the energy rho (c A)^2/L", log10(config%density) + log_ratio + 2*log10(config%amplitude) - &
                     log10(config%length))
         call within("the error measure's scale rho L (A/100)^2", log10(config%density) + log10(config%length) + &
                     2*log10(config%amplitude) - 4)
         return
      end if
      if (trim(config%scene_kind) == 'plastic_wave') then
         ! the energy balance sums m v^2/2 and the drive's work V sum m v as they stand
         extra = ", drive_velocity = "//short_number(config%drive_velocity)//" m/s"
         call within("the drive's work rho V^2 L", log10(config%density) + 2*log10(config%drive_velocity) + &
                     log10(config%length))
         call within("the stress rho c V", log10(config%density) + log_ratio/2 + log10(config%drive_velocity))
         return
      end if
      if (trim(config%scene_kind) /= 'vibrating_bar' .or. config%velocity_amplitude == 0.0_dp) return
      log_c = log_ratio/2
      log_v = log10(abs(config%velocity_amplitude))
      ! the free end's amplitude in cells, |v0|/c 2 elements/((2 mode - 1) pi): the grid's margin holds it
      log_cells = log_v - log_c + log10(2*real(config%elements, dp)/((2*real(config%mode, dp) - 1)*pi))
      if (log_cells > 8 .and. config%margin_cells < 0) then
         call append_error(error, "scene: velocity_amplitude = "//short_number(config%velocity_amplitude)// &
                           " m/s moves the free end by about 1e"//str(nint(log_cells))//" cells (|v0|/c = 1e"// &
                           str(nint(log_v - log_c))//" with c = sqrt(youngs_modulus/density) = "// &
                           short_number(10.0_dp**log_c)//" m/s); allowed: an amplitude of at most 1e8 cells, "// &
                           "|velocity_amplitude| <= "//short_number(10.0_dp**(log_c + 8 - log_cells + log_v))//" m/s")
      else if (log_v - log_c + log10(config%length) < bottom + 1) then
         ! the exact u_cm amplitude v0/(omega beta L) = (v0/c) L (2/((2n-1) pi))^2 must be a normal double
         call append_error(error, "scene: velocity_amplitude = "//short_number(config%velocity_amplitude)// &
                           " m/s, length = "//short_number(config%length)//" m and "//material()//" give "// &
                           "displacements of about (v0/c) L = 1e"//str(nint(log_v - log_c + log10(config%length)))// &
                           " m, below the doubles (2.2e-307); allowed: a larger velocity_amplitude or length")
      else if (log10(config%density) + 2*log_v + log10(config%length) - log10(4.0_dp) > top - 1) then
         call append_error(error, "scene: density = "//short_number(config%density)//" kg/m^3, velocity_amplitude"// &
                           " = "//short_number(config%velocity_amplitude)//" m/s and length = "// &
                           short_number(config%length)//" m give an energy rho v0^2 L/4 of 1e"// &
                           str(nint(log10(config%density) + 2*log_v + log10(config%length) - log10(4.0_dp)))// &
                           " J/m^2, beyond the doubles; allowed: rho v0^2 L/4 < 1.8e307")
      else if ((log10(config%youngs_modulus) + log10(config%density))/2 + log_v > top - 1) then
         call append_error(error, "scene: "//material()//" with velocity_amplitude = "// &
                           short_number(config%velocity_amplitude)//" m/s give a stress amplitude sqrt(E rho) |v0| "// &
                           "beyond the doubles; allowed: sqrt(youngs_modulus density) |velocity_amplitude| < 1.8e307 Pa")
      end if
   contains
      !> Refuse the scene when a product its formulas form (log10 `magnitude`) leaves the doubles.
      subroutine within(what, magnitude)
         character(len=*), intent(in) :: what
         real(dp), intent(in) :: magnitude
         if (magnitude < bottom + 2 .or. magnitude > top - 2) call append_error(error, "scene: kind = '"// &
            trim(config%scene_kind)//"' with length = "//short_number(config%length)//" m"//extra//" and "//material()// &
            ": "//what//" is about 1e"//str(nint(magnitude))//", beyond what its formulas hold in doubles; "// &
            "allowed: 1e-306 to 1e306 (choose units nearer 1; the vibrating bar's formulas are scaled, these are not)")
      end subroutine within
      !> The material's values, for a message (formed only then: for every case of a sweep, the
      !> numbers' text was 0.1 % of the paper's Table-2 sweeps).
      function material() result(text)
         character(len=:), allocatable :: text
         text = "youngs_modulus = "//short_number(config%youngs_modulus)//" Pa and density = "// &
                short_number(config%density)//" kg/m^3"
      end function material
   end subroutine check_representable

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
      real(dp) :: omega
      if (trim(config%integrator) == 'quasi_static') then ! the full load
         run_end_time = 1.0_dp
      else if (config%end_time_given .or. .not. ieee_is_nan(config%end_time)) then
         run_end_time = config%end_time
      else if (trim(config%scene_kind) == 'vibrating_bar') then ! this association: the paper's step counts
         omega = (2*config%mode - 1)*pi/(2.0_dp*config%length)*sqrt(config%youngs_modulus/config%density)
         run_end_time = config%periods*2.0_dp*pi/omega
      else
         ! the impact's periods count from the bars' first contact (0 when they meet at once or never)
         run_end_time = contact_time(config) + config%periods*scene_period(config)
      end if
   end function run_end_time

   !> When the impact's bars first touch: gap/(v1 - v2) when bar 1 is faster toward bar 2, else 0 (they
   !> touch at once or never); 0 for the other scenes.
   pure real(dp) function contact_time(config)
      type(config_t), intent(in) :: config
      contact_time = 0.0_dp
      if (trim(config%scene_kind) /= 'impact' .or. config%velocity_count /= 2) return
      if (config%velocities(1) > config%velocities(2)) &
         contact_time = config%gap/(config%velocities(1) - config%velocities(2))
   end function contact_time

   !> The time step of a validated configuration: dt = dt_fraction dx/c, c the fastest wave speed; for
   !> integrator quasi_static the load increment 1/load_steps (its "time" is the load factor, 0 to 1).
   pure real(dp) function time_step(config)
      type(config_t), intent(in) :: config
      if (trim(config%integrator) == 'quasi_static') then
         time_step = 1.0_dp/config%load_steps
      else
         time_step = config%dt_fraction*(body_length(config)/config%elements)/largest_wave_speed(config)
      end if
   end function time_step

   !> How far a free end can move out over a run of `end_time` (m): the scene's automatic grid margin
   !> holds it (mpm_scene_*: margin_cells). The bar: the end's amplitude |v0|/omega_n; the column: its
   !> sag g L^2/c^2; the composite bar: 4 v T (a transmitted wave's particle velocity is at most 2 v,
   !> doubled at the free end); the impact: 1.5 max |v_b| T on either side; the manufactured solution
   !> has no free end.
   pure real(dp) function free_end_reach(config, end_time) result(reach)
      type(config_t), intent(in) :: config
      real(dp), intent(in) :: end_time
      real(dp) :: c
      c = largest_wave_speed(config)
      select case (trim(config%scene_kind))
      case ('vibrating_bar')
         reach = abs(config%velocity_amplitude)/((2*real(config%mode, dp) - 1)*pi/(2.0_dp*config%length)*c)
      case ('column')
         reach = config%gravity*config%length**2/c**2
      case ('composite_bar')
         reach = 4.0_dp*config%drive_velocity*end_time
      case ('impact')
         reach = 1.5_dp*maxval(abs(config%velocities(1:2)))*end_time
      case default
         reach = 0.0_dp
      end select
   end function free_end_reach

   !> The empty cells the scene's grid gets beyond its free ends when margin_cells = -1: its reach in
   !> cells plus 2 on each free end (the impact has two), as mpm_scene's margin_for counts them.
   integer(i8) function automatic_margin(config)
      type(config_t), intent(in) :: config
      real(dp) :: cells
      automatic_margin = 0
      if (config%margin_cells >= 0) return
      cells = free_end_reach(config, run_end_time(config))/(body_length(config)/config%elements)
      if (.not. (cells <= 1.0e9_dp)) cells = 1.0e9_dp
      automatic_margin = 2 + ceiling(cells, i8)
      if (trim(config%scene_kind) == 'impact') automatic_margin = 2*automatic_margin
      if (trim(config%scene_kind) == 'manufactured') automatic_margin = 0
   end function automatic_margin

   !> The length of the body: the composite bar's segments together, else `length`.
   pure real(dp) function body_length(config)
      type(config_t), intent(in) :: config
      if (trim(config%scene_kind) == 'composite_bar') then
         body_length = sum(config%lengths(1:config%length_count))
      else if (trim(config%scene_kind) == 'impact') then ! both bars and the gap
         body_length = sum(config%lengths(1:2)) + config%gap
      else
         body_length = config%length
      end if
   end function body_length

   !> The wave speed the time step follows: the stiffest segment's of a composite bar, else sqrt(E/rho).
   pure real(dp) function largest_wave_speed(config)
      type(config_t), intent(in) :: config
      integer :: n
      if (trim(config%scene_kind) == 'composite_bar' .or. trim(config%scene_kind) == 'impact') then
         n = config%length_count
         largest_wave_speed = maxval(sqrt(config%youngs_moduli(1:n)/config%densities(1:n)))
      else
         largest_wave_speed = sqrt(config%youngs_modulus/config%density)
      end if
   end function largest_wave_speed

   !> The period that `periods` counts: the bar's mode n, 2 pi/omega_n; the column's first mode, 4L/c;
   !> the manufactured solution's, 2L/c (u oscillates as sin(pi c t/L)); the composite bar's: the time
   !> a wave takes to cross all segments, sum L_i/c_i.
   real(dp) function scene_period(config)
      type(config_t), intent(in) :: config
      real(dp) :: c
      c = sqrt(config%youngs_modulus/config%density)
      select case (trim(config%scene_kind))
      case ('column')
         scene_period = 4.0_dp*config%length/c
      case ('manufactured')
         scene_period = 2.0_dp*config%length/c
      case ('composite_bar')
         associate (n => config%length_count)
            scene_period = sum(config%lengths(1:n)/sqrt(config%youngs_moduli(1:n)/config%densities(1:n)))
         end associate
      case ('plastic_wave') ! the elastic precursor's transit time
         scene_period = config%length/c
      case ('impact') ! the longer of the bars' wave round trips 2 L/c (identical bars: the contact time)
         scene_period = 2.0_dp*maxval(config%lengths(1:2)/sqrt(config%youngs_moduli(1:2)/config%densities(1:2)))
      case default
         scene_period = 2.0_dp*pi/((2*config%mode - 1)*pi/(2.0_dp*config%length)*c)
      end select
   end function scene_period

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
      if (trim(config%scene_kind) == 'composite_bar' .or. trim(config%scene_kind) == 'impact') &
         config%length = body_length(config)
      config%wave_speed = largest_wave_speed(config)
      config%dx = config%length/config%elements
      config%dt = time_step(config)
      config%period = scene_period(config)
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
      defaults = config_t()
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
