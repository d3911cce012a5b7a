!> A scene's input: its own parameters as the namelist gives them (registry entries it contributes,
!> bound to its fields), what it needs of them together (its checks and their messages), what the
!> run's resolution asks of it (the body's length and fastest wave speed, the period `periods` counts,
!> how far a free end moves, the margins) and the scene it makes. The run's configuration (mpm_config)
!> aggregates the input of the chosen kind with the common settings (mpm_settings) and names no scene;
!> mpm_scenes lists the kinds. Two bases carry what several scenes share: body_input_t (one body of one
!> material: length, youngs_modulus, density, and the elastoplastic law's yield_stress and
!> hardening_modulus) and bodies_input_t (segments or bars of their own material: the lists lengths,
!> youngs_moduli, densities, yield_stresses, hardening_moduli).
module mpm_scene_input
   use, intrinsic :: ieee_arithmetic, only: ieee_is_nan
   use mpm_kinds, only: dp
   use mpm_errors, only: error_t, append_error
   use mpm_strings, only: str, num
   use mpm_settings, only: settings_t, max_segments
   use mpm_registry, only: parameter_t, real_entry, real_list_entry, for_value, short_number, place
   use mpm_material, only: material_t, law_id
   use mpm_scene, only: scene_t
   implicit none
   private
   public :: scene_input_t, scene_kind_t, body_input_t, bodies_input_t, drive_entry, body_representable, refuse_beyond_doubles
   public :: most_margin_cells

   !> The most cells the grid's automatic margin may add for a moving end (margin_overflow).
   real(dp), parameter :: most_margin_cells = 1.0e8_dp

   !> A scene kind as --help and the help of `kind` and `periods` describe it: its name, what it is, and
   !> the period `periods` counts in it.
   type :: scene_kind_t
      character(len=16) :: name = ''
      character(len=64) :: what = ''
      character(len=48) :: period = ''
   end type scene_kind_t

   type, abstract :: scene_input_t
   contains
      !> Its kind: name, what it is, the period `periods` counts.
      procedure(describe_i), deferred, nopass :: describe
      !> Its kind's name.
      procedure :: describe_name
      !> Its entries of &scene and of &material (the law's parameters of its body or bodies), bound to
      !> its fields (which must stay in place while the table is used), in the order of the echo and of a
      !> sweep's loops.
      procedure(entries_i), deferred :: entries
      procedure :: material_entries
      !> What it needs of its values together, with the settings (each value's range is checked on its
      !> own); messages start with `place` of the variable blamed (the file and line it was given at).
      procedure :: check
      !> What it needs of the run: its length `end_time`, the cell size dx (a free end's motion the
      !> grid's margin holds, a solution that stops holding); `length_text` says how the input gave the
      !> run's length, for a message about it.
      procedure :: check_run
      !> Values whose products its formulas form must stay within the doubles.
      procedure :: check_representable
      !> The length the grid's elements span (m), the fastest wave speed (the time step follows it), the
      !> period `periods` counts (s).
      procedure(real_i), deferred :: body_length, wave_speed, period
      !> The time from which periods count (the impact's first contact), default 0.
      procedure :: periods_from
      !> The end time of a run of `settings%periods` periods.
      procedure :: end_time
      !> The run length in periods when the input gives neither periods nor end_time (< 0: the settings').
      procedure :: default_periods
      !> The law when the input gives none ('': the settings').
      procedure :: default_law
      !> How far a free end moves out over a run of `end_time` (m; default 0: none moves out), and how
      !> many free ends the grid's automatic margin is beyond (default 1).
      procedure :: reach, free_ends
      !> The cells the automatic margin would need beyond the allowed (margin_overflow), and the middle of
      !> the message that refuses it (margin_overflow_text).
      procedure :: margin_overflow, margin_overflow_text
      !> Whether its loads are static with an exact static solution (integrator 'quasi_static').
      procedure :: static_loads
      !> Warnings about a valid run that misses what it is for ('' when none).
      procedure :: warnings
      !> What a message about the run's length adds after "end time ... s" ('' default), the message of
      !> a run shorter than one step when the scene's own variable is the cause ('' default), and of a run
      !> of too many steps when its wave speeds are the cause (`advice` then prefixed).
      procedure :: start_note, short_run, fast_waves
      !> What sets the amplitude of an error measured on displacements (u_cm, the column's, the
      !> manufactured solution's): named when that amplitude sinks to rounding. '' (the default): the
      !> scene's error is measured on stresses, which keep their digits at any amplitude.
      procedure :: amplitude_source
      !> The material of its body (of a body of several materials: the first segment's).
      procedure(material_i), deferred :: material
      !> The scene of a validated and resolved configuration.
      procedure(make_i), deferred :: make
   end type scene_input_t

   abstract interface
      pure function describe_i() result(kind)
         import :: scene_kind_t
         type(scene_kind_t) :: kind
      end function describe_i
      subroutine entries_i(self, table)
         import :: scene_input_t, parameter_t
         class(scene_input_t), intent(inout), target :: self
         type(parameter_t), allocatable, intent(out) :: table(:)
      end subroutine entries_i
      pure real(dp) function real_i(self)
         import :: scene_input_t, dp
         class(scene_input_t), intent(in) :: self
      end function real_i
      pure function material_i(self, law) result(material)
         import :: scene_input_t, material_t
         class(scene_input_t), intent(in) :: self
         character(len=*), intent(in) :: law
         type(material_t) :: material
      end function material_i
      subroutine make_i(self, settings, scene, error)
         import :: scene_input_t, settings_t, scene_t, error_t
         class(scene_input_t), intent(in) :: self
         class(settings_t), intent(in) :: settings
         class(scene_t), allocatable, intent(out) :: scene
         type(error_t), allocatable, intent(out) :: error
      end subroutine make_i
   end interface

   !> One body of one material.
   type, abstract, extends(scene_input_t) :: body_input_t
      real(dp) :: length = 25.0_dp
      real(dp) :: youngs_modulus = 200.0e9_dp
      real(dp) :: density = 7800.0_dp
      real(dp) :: yield_stress = 250.0e6_dp
      real(dp) :: hardening_modulus = 10.0e9_dp
   contains
      procedure :: body_entries, material_entries => body_material_entries, material => body_material
      procedure :: body_length => body_body_length, wave_speed => body_wave_speed
      procedure :: check_representable => body_representable
   end type body_input_t

   !> Segments (or bars) of their own material, left to right; `count` of each list given.
   type, abstract, extends(scene_input_t) :: bodies_input_t
      real(dp) :: lengths(max_segments) = 0.0_dp, youngs_moduli(max_segments) = 0.0_dp, &
                  densities(max_segments) = 0.0_dp
      integer :: length_count = 0, modulus_count = 0, density_count = 0
      real(dp) :: yield_stresses(max_segments) = 0.0_dp, hardening_moduli(max_segments) = 0.0_dp
      integer :: yield_count = 0, hardening_count = 0
   contains
      procedure :: bodies_entries, material_entries => bodies_material_entries, material => bodies_material
      procedure :: wave_speed => bodies_wave_speed, check_bodies_material, fast_waves => bodies_fast_waves
      procedure :: check_representable => bodies_representable
      !> What its messages call one of its parts ('segment', 'bar').
      procedure(part_i), deferred, nopass :: part
   end type bodies_input_t

   abstract interface
      pure function part_i() result(name)
         character(len=:), allocatable :: name
      end function part_i
   end interface

contains

   ! ------------------------------------------------------------------ defaults of scene_input_t

   function describe_name(self) result(name)
      class(scene_input_t), intent(in) :: self
      character(len=:), allocatable :: name
      type(scene_kind_t) :: kind
      kind = self%describe()
      name = trim(kind%name)
   end function describe_name

   !> No parameters in &material (a scene whose body takes no law's parameters).
   subroutine material_entries(self, table)
      class(scene_input_t), intent(inout), target :: self
      type(parameter_t), allocatable, intent(out) :: table(:)
      allocate (table(0))
   end subroutine material_entries

   subroutine check(self, settings, error, given)
      class(scene_input_t), intent(in) :: self
      class(settings_t), intent(in) :: settings
      type(error_t), allocatable, intent(inout) :: error
      type(parameter_t), intent(in), optional :: given(:)
   end subroutine check

   subroutine check_run(self, settings, end_time, dx, length_text, error, given)
      class(scene_input_t), intent(in) :: self
      class(settings_t), intent(in) :: settings
      real(dp), intent(in) :: end_time, dx
      character(len=*), intent(in) :: length_text
      type(error_t), allocatable, intent(inout) :: error
      type(parameter_t), intent(in), optional :: given(:)
   end subroutine check_run

   subroutine check_representable(self, settings, error)
      class(scene_input_t), intent(in) :: self
      class(settings_t), intent(in) :: settings
      type(error_t), allocatable, intent(inout) :: error
   end subroutine check_representable

   pure real(dp) function periods_from(self)
      class(scene_input_t), intent(in) :: self
      periods_from = 0.0_dp
   end function periods_from

   !> From periods_from, `settings%periods` of the scene's period.
   real(dp) function end_time(self, settings)
      class(scene_input_t), intent(in) :: self
      class(settings_t), intent(in) :: settings
      end_time = self%periods_from() + settings%periods*self%period()
   end function end_time

   pure real(dp) function default_periods(self)
      class(scene_input_t), intent(in) :: self
      default_periods = -1.0_dp
   end function default_periods

   function default_law(self) result(law)
      class(scene_input_t), intent(in) :: self
      character(len=:), allocatable :: law
      law = ''
   end function default_law

   pure real(dp) function reach(self, end_time)
      class(scene_input_t), intent(in) :: self
      real(dp), intent(in) :: end_time
      reach = 0.0_dp
   end function reach

   !> The cells of dx that the grid's automatic margin needs to hold the scene's moving ends over a run
   !> of `end_time` (its reach), when that is more than most_margin_cells; 0 when it is not, or when the
   !> input gives the margin (settings%margin_cells >= 0).
   real(dp) function margin_overflow(self, settings, end_time, dx) result(cells)
      class(scene_input_t), intent(in) :: self
      class(settings_t), intent(in) :: settings
      real(dp), intent(in) :: end_time, dx
      cells = 0.0_dp
      if (settings%margin_cells >= 0) return
      cells = self%reach(end_time)/dx
      if (.not. (cells > most_margin_cells)) cells = 0.0_dp
   end function margin_overflow

   !> "<reach> m over the run (T = <end_time> s), about <cells> cells of dx = <dx> m for the grid's
   !> <margins> to hold; allowed: at most 1e8 cells, ": the message of a margin_overflow after the words
   !> that name the scene's moving ends, before the bound on its own variable.
   function margin_overflow_text(self, end_time, dx, cells, margins) result(text)
      class(scene_input_t), intent(in) :: self
      real(dp), intent(in) :: end_time, dx, cells
      character(len=*), intent(in) :: margins
      character(len=:), allocatable :: text
      text = num(self%reach(end_time), 4)//" m over the run (T = "//num(end_time, 4)//" s), about "// &
             num(cells, 3)//" cells of dx = "//num(dx, 4)//" m for the grid's "//margins// &
             " to hold; allowed: at most 1e8 cells, "
   end function margin_overflow_text

   pure integer function free_ends(self)
      class(scene_input_t), intent(in) :: self
      free_ends = 1
   end function free_ends

   pure logical function static_loads(self)
      class(scene_input_t), intent(in) :: self
      static_loads = .false.
   end function static_loads

   function warnings(self, settings) result(text)
      class(scene_input_t), intent(in) :: self
      class(settings_t), intent(in) :: settings
      character(len=:), allocatable :: text
      text = ''
   end function warnings

   function start_note(self, end_time) result(text)
      class(scene_input_t), intent(in) :: self
      real(dp), intent(in) :: end_time
      character(len=:), allocatable :: text
      text = ''
   end function start_note

   function amplitude_source(self) result(text)
      class(scene_input_t), intent(in) :: self
      character(len=:), allocatable :: text
      text = ''
   end function amplitude_source

   function short_run(self, settings, end_time, dt, given) result(text)
      class(scene_input_t), intent(in) :: self
      class(settings_t), intent(in) :: settings
      real(dp), intent(in) :: end_time, dt
      type(parameter_t), intent(in), optional :: given(:)
      character(len=:), allocatable :: text
      text = ''
   end function short_run

   !> '' (the default): the run's steps follow one wave speed.
   subroutine fast_waves(self, settings, text, advice, given)
      class(scene_input_t), intent(in) :: self
      class(settings_t), intent(in) :: settings
      character(len=:), allocatable, intent(out) :: text, advice
      type(parameter_t), intent(in), optional :: given(:)
      text = ''
      advice = ''
   end subroutine fast_waves

   ! ------------------------------------------------------------------ one body of one material

   !> The body's entries of &scene: length, youngs_modulus, density.
   subroutine body_entries(self, table)
      class(body_input_t), intent(inout), target :: self
      type(parameter_t), allocatable, intent(out) :: table(:)
      table = [real_entry('scene', 'length', self%length, 'm', 'length of the bar', greater_than=0.0_dp), &
               real_entry('scene', 'youngs_modulus', self%youngs_modulus, 'Pa', "Young's modulus E", &
                          greater_than=0.0_dp, sweep_list='youngs_moduli'), &
               real_entry('scene', 'density', self%density, 'kg/m^3', 'density rho', greater_than=0.0_dp, &
                          sweep_list='densities')]
   end subroutine body_entries

   !> The elastoplastic law's parameters of the body.
   subroutine body_material_entries(self, table)
      class(body_input_t), intent(inout), target :: self
      type(parameter_t), allocatable, intent(out) :: table(:)
      table = [for_value(real_entry('material', 'yield_stress', self%yield_stress, 'Pa', 'initial yield stress '// &
                                    'sigma_y: |sigma| <= sigma_y + H alpha (law elastoplastic)', greater_than=0.0_dp, &
                                    sweep_list='yield_stress'), 'law', 'elastoplastic'), &
               for_value(real_entry('material', 'hardening_modulus', self%hardening_modulus, 'Pa', 'linear isotropic '// &
                                    'hardening modulus H (law elastoplastic; 0: perfectly plastic)', at_least=0.0_dp, &
                                    sweep_list='hardening_modulus'), 'law', 'elastoplastic')]
   end subroutine body_material_entries

   pure function body_material(self, law) result(material)
      class(body_input_t), intent(in) :: self
      character(len=*), intent(in) :: law
      type(material_t) :: material
      material%law = law_id(law)
      material%youngs_modulus = self%youngs_modulus
      if (trim(law) == 'elastoplastic') then
         material%yield_stress = self%yield_stress
         material%hardening_modulus = self%hardening_modulus
      end if
   end function body_material

   pure real(dp) function body_body_length(self)
      class(body_input_t), intent(in) :: self
      body_body_length = self%length
   end function body_body_length

   pure real(dp) function body_wave_speed(self)
      class(body_input_t), intent(in) :: self
      body_wave_speed = sqrt(self%youngs_modulus/self%density)
   end function body_wave_speed

   !> A wave speed sqrt(E/rho) doubles can hold (compared as logarithms, so that the check cannot overflow).
   subroutine body_representable(self, settings, error)
      class(body_input_t), intent(in) :: self
      class(settings_t), intent(in) :: settings
      type(error_t), allocatable, intent(inout) :: error
      real(dp), parameter :: top = log10(huge(1.0_dp)), bottom = log10(tiny(1.0_dp))
      real(dp) :: log_ratio
      log_ratio = log10(self%youngs_modulus) - log10(self%density)
      if (log_ratio > top .or. log_ratio < bottom) &
         call append_error(error, "scene: youngs_modulus = "//short_number(self%youngs_modulus)//" Pa and density = "// &
                           short_number(self%density)//" kg/m^3 give no wave speed sqrt(E/rho) doubles can hold "// &
                           "(E/rho = 1e"//str(nint(log_ratio))//"); allowed: 2.2e-308 <= youngs_modulus/density <= 1.8e308")
   end subroutine body_representable

   ! ------------------------------------------------------------------ segments of their own material

   !> The segments' (bars') entries of &scene: lengths, youngs_moduli, densities.
   subroutine bodies_entries(self, table)
      class(bodies_input_t), intent(inout), target :: self
      type(parameter_t), allocatable, intent(out) :: table(:)
      table = [real_list_entry('scene', 'lengths', self%lengths, self%length_count, 'm', 'segment lengths, '// &
                               'left (driven end) to right (free end); impact: bar 1, bar 2', greater_than=0.0_dp, &
                               note='2 to 16 segments; impact: 2'), &
               real_list_entry('scene', 'youngs_moduli', self%youngs_moduli, self%modulus_count, 'Pa', &
                               "each segment's (bar's) Young's modulus", greater_than=0.0_dp, note='one per segment'), &
               real_list_entry('scene', 'densities', self%densities, self%density_count, 'kg/m^3', &
                               "each segment's (bar's) density", greater_than=0.0_dp, note='one per segment')]
   end subroutine bodies_entries

   !> The elastoplastic law's parameters, one per segment (bar).
   subroutine bodies_material_entries(self, table)
      class(bodies_input_t), intent(inout), target :: self
      type(parameter_t), allocatable, intent(out) :: table(:)
      table = [for_value(real_list_entry('material', 'yield_stresses', self%yield_stresses, self%yield_count, 'Pa', &
                                         "each segment's (bar's) yield stress (law elastoplastic)", greater_than=0.0_dp, &
                                         note='one per segment'), 'law', 'elastoplastic'), &
               for_value(real_list_entry('material', 'hardening_moduli', self%hardening_moduli, self%hardening_count, &
                                         'Pa', "each segment's (bar's) hardening modulus (law elastoplastic)", &
                                         at_least=0.0_dp, note='one per segment'), 'law', 'elastoplastic')]
   end subroutine bodies_material_entries

   !> The first segment's material (each particle carries its own segment's: the scene sets them).
   pure function bodies_material(self, law) result(material)
      class(bodies_input_t), intent(in) :: self
      character(len=*), intent(in) :: law
      type(material_t) :: material
      material%law = law_id(law)
      material%youngs_modulus = self%youngs_moduli(1)
      if (trim(law) == 'elastoplastic') then
         material%yield_stress = self%yield_stresses(1)
         material%hardening_modulus = self%hardening_moduli(1)
      end if
   end function bodies_material

   !> The stiffest segment's wave speed.
   pure real(dp) function bodies_wave_speed(self)
      class(bodies_input_t), intent(in) :: self
      associate (n => self%length_count)
         bodies_wave_speed = maxval(sqrt(self%youngs_moduli(1:n)/self%densities(1:n)))
      end associate
   end function bodies_wave_speed

   !> An elastoplastic body of several materials needs yield_stresses and hardening_moduli, one per segment.
   subroutine check_bodies_material(self, settings, error)
      class(bodies_input_t), intent(in) :: self
      class(settings_t), intent(in) :: settings
      type(error_t), allocatable, intent(inout) :: error
      if (trim(settings%law) == 'elastoplastic' .and. (self%yield_count /= self%length_count .or. &
                                                      self%hardening_count /= self%length_count)) &
         call append_error(error, "material: law = 'elastoplastic' with kind = '"//trim(self%describe_name())// &
                           "' needs yield_stresses and hardening_moduli with one value per segment (given "// &
                           str(self%yield_count)//" and "//str(self%hardening_count)//" for "// &
                           str(self%length_count)//" segments)")
   end subroutine check_bodies_material

   !> A large contrast of wave speeds: the step follows the fastest wave, the period the slower ones.
   subroutine bodies_fast_waves(self, settings, text, advice, given)
      class(bodies_input_t), intent(in) :: self
      class(settings_t), intent(in) :: settings
      character(len=:), allocatable, intent(out) :: text, advice
      type(parameter_t), intent(in), optional :: given(:)
      real(dp), allocatable :: c(:)
      integer :: fast, slow
      character(len=:), allocatable :: part
      text = ''
      advice = ''
      c = sqrt(self%youngs_moduli(1:self%length_count)/self%densities(1:self%length_count))
      fast = maxloc(c, 1)
      slow = minloc(c, 1)
      if (.not. (c(fast) > 100*c(slow))) return
      part = self%part()
      text = place(given, 'scene', 'youngs_moduli')//"scene: youngs_moduli("//str(fast)//") = "// &
             short_number(self%youngs_moduli(fast))//" Pa and densities("//str(fast)//") = "// &
             short_number(self%densities(fast))//" kg/m^3 give "//part//" "//str(fast)//" a wave "// &
             "speed of "//num(c(fast), 4)//" m/s, "//num(c(fast)/c(slow), 3)//" times "//part//" "// &
             str(slow)//"'s ("//num(c(slow), 4)//" m/s): dt follows the fastest wave, the period the "// &
             "slower ones, so "
      advice = "wave speeds sqrt(youngs_moduli/densities) closer together, "
   end subroutine bodies_fast_waves

   !> E/rho of each segment within the doubles.
   subroutine bodies_representable(self, settings, error)
      class(bodies_input_t), intent(in) :: self
      class(settings_t), intent(in) :: settings
      type(error_t), allocatable, intent(inout) :: error
      real(dp), parameter :: top = log10(huge(1.0_dp)), bottom = log10(tiny(1.0_dp))
      real(dp) :: log_ratio
      integer :: k
      do k = 1, self%length_count
         log_ratio = log10(self%youngs_moduli(k)) - log10(self%densities(k))
         if (log_ratio > top .or. log_ratio < bottom) call append_error(error, "scene: youngs_moduli("// &
            str(k)//") = "//short_number(self%youngs_moduli(k))//" Pa and densities("//str(k)//") = "// &
            short_number(self%densities(k))//" kg/m^3 give E/rho = 1e"//str(nint(log_ratio))// &
            ", beyond the doubles; allowed: 2.2e-308 <= youngs_moduli/densities <= 1.8e308")
      end do
   end subroutine bodies_representable

   !> The drive velocity's entry (the scenes driven at their left end).
   function drive_entry(drive_velocity) result(p)
      real(dp), intent(inout), target :: drive_velocity
      type(parameter_t) :: p
      p = real_entry('scene', 'drive_velocity', drive_velocity, 'm/s', 'velocity the left end '// &
                     'is driven at from t = 0 (pushing into the bar)', greater_than=0.0_dp, &
                     sweep_list='drive_velocities')
   end function drive_entry

   !> Refuse a scene (`scene`: its kind and values) when a product its formulas form, `what` of about
   !> 1e`magnitude`, lies within a factor 100 of the doubles' range.
   subroutine refuse_beyond_doubles(error, scene, what, magnitude)
      type(error_t), allocatable, intent(inout) :: error
      character(len=*), intent(in) :: scene, what
      real(dp), intent(in) :: magnitude
      real(dp), parameter :: top = log10(huge(1.0_dp)), bottom = log10(tiny(1.0_dp))
      if (magnitude < bottom + 2 .or. magnitude > top - 2) call append_error(error, "scene: "//scene//": "// &
         what//" is about 1e"//str(nint(magnitude))//", beyond what its formulas hold in doubles; allowed: "// &
         "1e-306 to 1e306 (choose units nearer 1; the vibrating bar's formulas are scaled, these are not)")
   end subroutine refuse_beyond_doubles
end module mpm_scene_input
