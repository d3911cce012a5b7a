!> The run's settings that are not a scene's own: the material law, the discretisation, the run's
!> length, the output and the guards, with their defaults (the paper's Table 1 and its verification
!> case), and the quantities resolved from them with the scene (mpm_config: resolve_config). A scene's
!> own parameters live in its input type (src/scene, scene_input_t); the run's whole configuration,
!> config_t (mpm_config), is these settings and the scene's input. Plain data: the registry entries
!> that read and check them are mpm_config's.
module mpm_settings
   use mpm_kinds, only: dp, i8
   implicit none
   private
   public :: settings_t, max_snapshots, max_segments

   !> Most snapshot times one run accepts.
   integer, parameter :: max_snapshots = 64
   !> Most segments of a body of several materials (the per-segment lists of the scenes and laws).
   integer, parameter :: max_segments = 16

   type :: settings_t
      ! &material: the constitutive law (its parameters are the scene's: one body's or one per segment)
      character(len=16) :: law = 'hencky'
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
      !> NaN until set: a program that fills the settings sets end_time alone (see mpm_config's
      !> run_length_flags); a user's NaN is refused by its range check, as it sets end_time_given.
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
      ! resolved (derived) quantities, filled by resolve_config from the settings and the scene
      !> the length of the body (or bodies, and the gaps between them) the grid's elements span (m)
      real(dp) :: length = 0.0_dp
      !> the Young's modulus of a body of one material (Pa; the fused bar's kernels take it); for bodies
      !> of several materials the first one's (each particle then carries its own)
      real(dp) :: youngs_modulus = 0.0_dp
      real(dp) :: wave_speed = 0.0_dp
      real(dp) :: dx = 0.0_dp
      real(dp) :: dt = 0.0_dp
      real(dp) :: period = 0.0_dp
      real(dp) :: final_time = 0.0_dp
      integer :: steps = 0
   end type settings_t
end module mpm_settings
