!> The step, named: a run advances its particles and grid by one abstract stepper, chosen once per run
!> (mpm_simulation), whose extensions are the ways mpm1d steps:
!>   generic_stepper_t   (mpm_schemes)     USF, USL, MUSL on the generic operations, any shape and
!>                                         transfer, one velocity field or one per body (contact);
!>   fused_stepper_t     (mpm_fused)       the same schemes on the fused kernels, where they apply;
!>   implicit_stepper_t  (mpm_implicit)    Newmark's trapezoidal rule or quasi-static load steps, Newton
!>                                         on the grid.
!> A new way of stepping (a formulation, an integrator) is one more extension. The stepper carries what
!> its path needs (a shape cache, the fused kernels' description, contact fields, Newton's workspace);
!> what every path shares (the particles, the run's grid, the problem's loads) is passed to it.
module mpm_stepper
   use mpm_kinds, only: dp
   use mpm_names, only: name_id
   use mpm_grid, only: grid_t
   use mpm_particles, only: particles_t
   use mpm_pass_totals, only: pass_totals_t
   use mpm_loads, only: loads_t
   use mpm_state, only: state_t
   implicit none
   private
   public :: stepper_t, stepper_stop_t, scheme_usf, scheme_usl, scheme_musl, scheme_id, known_schemes

   !> The explicit update schemes (docs/theory.md, Algorithm).
   integer, parameter :: scheme_usf = 1, scheme_usl = 2, scheme_musl = 3
   !> Their names, in the order of the ids (mpm_names).
   character(len=*), parameter :: known_schemes = 'usf, usl, musl'

   !> Why a stepper could not complete a step (an implicit step whose Newton iteration failed): what the
   !> guard reports. `stopped` false: the step completed. `stretched`: a step that completed but left a
   !> CPDI particle's domain over more nodes than its weights reach (that particle; 0: none).
   type :: stepper_stop_t
      logical :: stopped = .false.
      real(dp) :: residual = 0.0_dp   !< the relative residual it stopped at
      integer :: iteration = 0        !< the linear solves made
      integer :: node = -1            !< the node of a singular matrix's zero pivot (-1: none)
      logical :: mass_matrix = .false.  !< the singular matrix was the consistent mass (else the tangent)
      integer :: stretched = 0
   end type stepper_stop_t

   type, abstract :: stepper_t
      !> The explicit scheme (scheme_usf, scheme_usl, scheme_musl; the implicit integrators ignore it).
      integer :: scheme = scheme_usl
   contains
      !> The state at t = 0: the first mapping a step expects, and the energies and smallest J of the
      !> particles as they are, in `totals`.
      procedure(start_i), deferred :: start
      !> One step from time t to t + dt.
      procedure(step_i), deferred :: step
      !> What totals%displacement is divided by for u_cm (the total mass, or the particle count where the
      !> kernels sum x - X of particles of one mass).
      procedure(mass_i), deferred :: displacement_mass
      !> The run's grid as a snapshot reads it: at step 0 the nodal velocity of the first mapping, later
      !> the nodal values of the last step (default: the grid holds them already after step 0).
      procedure(snapshot_grid_i), deferred :: snapshot_grid
      !> Why the last step could not complete (default: it did).
      procedure :: stop_reason
      !> What the stepper reports in the run's /summary (default: nothing).
      procedure :: report
      !> What it carries from one step to the next, to or from a checkpoint's state (as state%saving
      !> says: back into a stepper set up for the same run; default: nothing).
      procedure :: sync_state
   end type stepper_t

   abstract interface
      subroutine start_i(self, loads, particles, grid, totals)
         import :: stepper_t, loads_t, particles_t, grid_t, pass_totals_t
         class(stepper_t), intent(inout) :: self
         class(loads_t), intent(in) :: loads
         type(particles_t), intent(inout) :: particles
         type(grid_t), intent(inout) :: grid
         type(pass_totals_t), intent(out) :: totals
      end subroutine start_i
      subroutine step_i(self, loads, particles, grid, dt, t, totals)
         import :: stepper_t, loads_t, particles_t, grid_t, pass_totals_t, dp
         class(stepper_t), intent(inout) :: self
         class(loads_t), intent(in) :: loads
         type(particles_t), intent(inout) :: particles
         type(grid_t), intent(inout) :: grid
         real(dp), intent(in) :: dt, t
         type(pass_totals_t), intent(out) :: totals
      end subroutine step_i
      real(dp) function mass_i(self, particles)
         import :: stepper_t, particles_t, dp
         class(stepper_t), intent(in) :: self
         type(particles_t), intent(in) :: particles
      end function mass_i
      subroutine snapshot_grid_i(self, particles, grid, step)
         import :: stepper_t, particles_t, grid_t
         class(stepper_t), intent(inout) :: self
         type(particles_t), intent(in) :: particles
         type(grid_t), intent(inout) :: grid
         integer, intent(in) :: step
      end subroutine snapshot_grid_i
   end interface

contains

   !> Integer id of a scheme name (0 if unknown; the configuration is validated before).
   pure integer function scheme_id(scheme)
      character(len=*), intent(in) :: scheme
      scheme_id = name_id(scheme, known_schemes)
   end function scheme_id

   pure function stop_reason(self) result(reason)
      class(stepper_t), intent(in) :: self
      type(stepper_stop_t) :: reason
      reason = stepper_stop_t()
   end function stop_reason

   subroutine report(self, names, values)
      class(stepper_t), intent(in) :: self
      character(len=32), allocatable, intent(out) :: names(:)
      real(dp), allocatable, intent(out) :: values(:)
      allocate (names(0), values(0))
   end subroutine report


   subroutine sync_state(self, state)
      class(stepper_t), intent(inout) :: self
      type(state_t), intent(inout) :: state
   end subroutine sync_state
end module mpm_stepper
