!> The scene layer's interface: everything problem-specific. A scene builds its bodies (particles
!> and their initial state), says how far the grid domain extends beyond them and which nodes are
!> held, registers the grid operations it needs (external forces: only when `external_forces` is
!> set, so a scene without them pays nothing), gives its exact solution and says whether the fused
!> kernels of the paper's bar apply to it. The simulation sees only this type; mpm_scenes makes one.
module mpm_scene
   use mpm_kinds, only: dp
   use mpm_errors, only: error_t
   use mpm_settings, only: settings_t
   use mpm_state, only: state_t
   use mpm_grid, only: grid_t, grid_loads_t
   use mpm_particles, only: particles_t
   use mpm_diagnostics, only: exact_name_length
   use mpm_pass_totals, only: pass_totals_t
   use mpm_shape, only: shape_cache_t
   use mpm_loads, only: loads_t
   implicit none
   private
   public :: scene_t, watch_t, margin_for, sine_profile, exact_name_length

   !> What a scene that watches every step keeps between steps: each such scene extends it with its own
   !> running values (watch_step makes it on the first step).
   type :: watch_t
   contains
      !> Save or restore its running values in a checkpoint (mpm_state; default: it has none).
      procedure :: sync => watch_sync
   end type watch_t

   !> A scene is the problem a run solves: its loads (mpm_loads, what the steppers see) and all the rest.
   type, abstract, extends(loads_t) :: scene_t
      !> Whether each body has its own velocity field on the grid (frictionless contact, mpm_contact):
      !> the scene places each body's particles as one contiguous range and sets particles%body.
      logical :: body_fields = .false.
      !> Whether the scene watches every step (watch_step) and reports what it saw (watch_report).
      logical :: watches = .false.
   contains
      !> Particles of the bodies, in their initial state (shared mass and volume; see per_particle_data).
      procedure(place_i), deferred :: place_particles
      !> Empty cells beyond the free end(s), given the cell size and the namelist's request (-1: automatic).
      procedure(margin_i), deferred :: margin_cells
      !> Nodes held at rest (boundary conditions).
      procedure(fixed_i), deferred :: fixed_nodes
      !> Exact centre-of-mass displacement at time t, and its amplitude (for relative errors).
      procedure(exact_i), deferred :: ucm_exact
      procedure(amplitude_i), deferred :: ucm_amplitude
      !> Whether the fused kernels may take the scene (default: no; the bar, column, composite bar,
      !> manufactured solution and impact say yes: mpm_fused's fused_choose then decides by the shape,
      !> the transfer and what the particles carry).
      procedure :: fused_applies
      !> The scene's error measure at time t from the particles (default: |u_cm - u_cm,exact(t)|);
      !> the run's max_error is its largest value over the steps, relative_error that / ucm_amplitude.
      procedure :: error_at
      !> What error_at measures and its unit (default m), for messages.
      procedure :: error_name, error_unit
      !> Quantities the scene reports in the run's /summary beyond the common ones (default: none).
      procedure :: report
      !> The energy that scales the energy guard (default: the initial kinetic + strain energy); scenes
      !> whose forces do work override it with the largest energy the exact solution reaches.
      procedure :: energy_reference
      !> Empty cells left of x = 0 (a free left end that moves out; default none).
      procedure :: left_margin_cells
      !> Called after every step when `watches`, in place of error_at: the scene keeps what it needs in
      !> `watch` (its own extension of watch_t, made by the scene on the first call) and gives the step's
      !> error measure (error_at's value; a scene may take both from one pass over its particles, or from
      !> the step's `totals`); watch_report turns `watch` into /summary quantities at the end.
      procedure :: watch_step, watch_report
      !> An empty watch of the scene's own type, for a checkpoint to fill (a restart).
      procedure :: new_watch
      !> The exact fields at reference positions x0 and time t, those the scene has (default: none):
      !> written beside each snapshot's particle fields.
      procedure :: exact_fields
   end type scene_t


   abstract interface
      subroutine place_i(self, settings, particles, error)
         import :: scene_t, settings_t, particles_t, error_t
         class(scene_t), intent(in) :: self
         class(settings_t), intent(in) :: settings
         type(particles_t), intent(out) :: particles
         type(error_t), allocatable, intent(out) :: error
      end subroutine place_i
      pure integer function margin_i(self, dx, requested)
         import :: scene_t, dp
         class(scene_t), intent(in) :: self
         real(dp), intent(in) :: dx
         integer, intent(in) :: requested
      end function margin_i
      pure function fixed_i(self) result(nodes)
         import :: scene_t
         class(scene_t), intent(in) :: self
         integer, allocatable :: nodes(:)
      end function fixed_i
      pure real(dp) function exact_i(self, t)
         import :: scene_t, dp
         class(scene_t), intent(in) :: self
         real(dp), intent(in) :: t
      end function exact_i
      pure real(dp) function amplitude_i(self)
         import :: scene_t, dp
         class(scene_t), intent(in) :: self
      end function amplitude_i
   end interface

contains

   !> v(p) = amplitude sin(wave_number x(p)) (the scenes' initial velocity profiles), one scalar sin
   !> per particle. Not vectorised on purpose: gfortran vectorises sin with glibc's vector functions
   !> (libmvec), which differ from the scalar sin in the last bit for some arguments, and how an array
   !> is split between the vector loop and its scalar peel and remainder depends on its length and on
   !> its address's alignment. The same case then started from different velocities in different
   !> runs of a two-thread sweep (1 ulp, kinetic energy from step 0; 2 of 6 MUSL paper sweeps).
   subroutine sine_profile(amplitude, wave_number, x, v)
      real(dp), intent(in) :: amplitude, wave_number
      real(dp), intent(in), contiguous :: x(:)
      real(dp), intent(out), contiguous :: v(:)
      integer :: p
      !GCC$ novector
      do p = 1, size(x)
         v(p) = amplitude*sin(wave_number*x(p))
      end do
   end subroutine sine_profile

   pure integer function left_margin_cells(self, dx, requested) result(cells)
      class(scene_t), intent(in) :: self
      real(dp), intent(in) :: dx
      integer, intent(in) :: requested
      cells = 0
   end function left_margin_cells

   subroutine watch_step(self, t, particles, totals, ucm, watch, error)
      class(scene_t), intent(in) :: self
      real(dp), intent(in) :: t, ucm
      type(particles_t), intent(in) :: particles
      type(pass_totals_t), intent(in) :: totals
      class(watch_t), allocatable, intent(inout) :: watch
      real(dp), intent(out) :: error
      error = self%error_at(t, particles, ucm)
   end subroutine watch_step

   subroutine new_watch(self, watch)
      class(scene_t), intent(in) :: self
      class(watch_t), allocatable, intent(out) :: watch
      allocate (watch_t :: watch)
   end subroutine new_watch

   subroutine watch_report(self, watch, particles, names, values)
      class(scene_t), intent(in) :: self
      class(watch_t), allocatable, intent(in) :: watch
      type(particles_t), intent(in) :: particles
      character(len=32), allocatable, intent(out) :: names(:)
      real(dp), allocatable, intent(out) :: values(:)
      allocate (names(0), values(0))
   end subroutine watch_report

   !> Empty cells beyond a free end that moves out by up to `reach` metres: `requested` when >= 0, else
   !> the reach in cells of size dx, rounded up, plus two (one for a particle's shape support, one of slack),
   !> at most 1e9 + 2 (the validation refuses a motion of more than 1e8 cells). The reach is capped before
   !> it is rounded to an integer: ceiling(reach/dx) of 1e10 cells or more, or of NaN, is no integer
   !> (it gave a negative margin, and a run that wrote outside its grid).
   pure integer function margin_for(reach, dx, requested) result(cells)
      real(dp), intent(in) :: reach, dx
      integer, intent(in) :: requested
      integer, parameter :: most = 1000000000
      if (requested >= 0) then
         cells = requested
      else if (reach/dx <= real(most, dp)) then
         cells = 2 + ceiling(reach/dx)
      else
         cells = 2 + most
      end if
   end function margin_for

   pure logical function fused_applies(self)
      class(scene_t), intent(in) :: self
      fused_applies = .false.
   end function fused_applies

   !> The founding paper's measure: |u_cm - u_cm,exact(t)| (m).
   real(dp) function error_at(self, t, particles, ucm)
      class(scene_t), intent(in) :: self
      real(dp), intent(in) :: t, ucm
      type(particles_t), intent(in) :: particles
      error_at = abs(ucm - self%ucm_exact(t))
   end function error_at

   pure subroutine report(self, names, values)
      class(scene_t), intent(in) :: self
      character(len=32), allocatable, intent(out) :: names(:)
      real(dp), allocatable, intent(out) :: values(:)
      allocate (names(0), values(0))
   end subroutine report

   pure function error_name(self) result(name)
      class(scene_t), intent(in) :: self
      character(len=:), allocatable :: name
      name = '|u_cm - u_cm,exact|'
   end function error_name

   pure function error_unit(self) result(unit)
      class(scene_t), intent(in) :: self
      character(len=:), allocatable :: unit
      unit = 'm'
   end function error_unit

   !> No exact field: `names` of the fields given (displacement, velocity, stress), `values(:, k)` field k
   !> at each of `x0` (m, m/s, Pa).
   pure subroutine exact_fields(self, x0, t, names, values)
      class(scene_t), intent(in) :: self
      real(dp), intent(in) :: x0(:), t
      character(len=exact_name_length), allocatable, intent(out) :: names(:)
      real(dp), allocatable, intent(out) :: values(:, :)
      allocate (names(0), values(size(x0), 0))
   end subroutine exact_fields

   !> The initial energy (a run starting at rest with no force keeps zero energy: any growth trips).
   pure real(dp) function energy_reference(self, initial_energy)
      class(scene_t), intent(in) :: self
      real(dp), intent(in) :: initial_energy
      energy_reference = max(initial_energy, tiny(1.0_dp))
   end function energy_reference
   subroutine watch_sync(self, state, name)
      class(watch_t), intent(inout) :: self
      type(state_t), intent(inout) :: state
      character(len=*), intent(in) :: name
   end subroutine watch_sync
end module mpm_scene
