!> Run outcome codes, the per-step history of a run and its snapshots.
module mpm_diagnostics
   use mpm_kinds, only: dp, i8
   use mpm_names, only: id_name
   implicit none
   private
   public :: no_value
   public :: status_ok, status_non_finite, status_volume_ratio, status_left_grid, status_energy_growth, &
             status_cell_crossing, status_setup_failed, status_not_run, status_name, status_newton, &
             status_domain_stretched
   public :: history_t, snapshot_t, exact_name_length

   !> Run status codes (stored in the HDF5 output; 0 means the run completed).
   integer, parameter :: status_ok = 0
   integer, parameter :: status_non_finite = 1     !< NaN or Infinity in the particle state
   integer, parameter :: status_volume_ratio = 2   !< a particle's J = V/V0 became <= 0
   integer, parameter :: status_left_grid = 3      !< a particle left the grid domain
   integer, parameter :: status_energy_growth = 4  !< total energy grew beyond the allowed factor
   integer, parameter :: status_cell_crossing = 5  !< a particle moved more than one cell in one step
   integer, parameter :: status_setup_failed = 6   !< the run could not be set up (memory)
   integer, parameter :: status_newton = 7         !< an implicit step's Newton iteration did not converge
   integer, parameter :: status_domain_stretched = 8 !< a CPDI particle domain outgrew the nodes it touches
   integer, parameter :: status_not_run = -1       !< a sweep case that has not run (yet), or was abandoned
   !> Their names, from status_not_run to status_domain_stretched (mpm_names).
   character(len=*), parameter :: status_names = 'not_run, ok, non_finite, volume_ratio_not_positive, '// &
                                                  'left_grid, energy_growth, cell_crossing, setup_failed, '// &
                                                  'newton_not_converged, domain_stretched'

   !> "No value": a quiet NaN (bits 7FF8000000000000), written where a result does not exist (the
   !> error of a run a guard stopped, the time of a case not timed); the status says why.
   real(dp), parameter :: no_value = transfer(9221120237041090560_i8, 1.0_dp)

   !> The length of an exact field's name in a snapshot (scene_t's exact_fields).
   integer, parameter :: exact_name_length = 16

   !> One entry per recorded step (step 0 = initial state).
   type :: history_t
      integer :: recorded = 0
      real(dp), allocatable :: time(:), ucm(:), ucm_exact(:), kinetic_energy(:), strain_energy(:)
      !> the plastic work at each step: allocated only when a body is elastoplastic
      real(dp), allocatable :: plastic_work(:)
   end type history_t

   !> Particle and grid state at one time.
   type :: snapshot_t
      real(dp) :: time = 0.0_dp
      integer :: step = 0
      real(dp), allocatable :: x(:), v(:), stress(:), volume_ratio(:)
      real(dp), allocatable :: x0(:)  !< reference (initial) positions X, for u = x - X and exact solutions
      !> each particle's Young's modulus, where the scene has several materials (their segment or body)
      real(dp), allocatable :: youngs_modulus(:)
      !> each particle's body, where the scene has several (impact)
      integer, allocatable :: body(:)
      !> each particle's plastic strain, where a body is elastoplastic
      real(dp), allocatable :: plastic_strain(:)
      real(dp), allocatable :: grid_x(:), grid_velocity(:)
      !> the scene's exact fields at each particle's reference position (names: displacement, velocity,
      !> stress; those the scene has), column k named exact_names(k)
      character(len=exact_name_length), allocatable :: exact_names(:)
      real(dp), allocatable :: exact(:, :)
   end type snapshot_t

contains

   !> Short name of a status code, as written to output files and messages.
   pure function status_name(code) result(name)
      integer, intent(in) :: code
      character(len=:), allocatable :: name
      name = id_name(code, status_names, first=status_not_run)
   end function status_name
end module mpm_diagnostics
