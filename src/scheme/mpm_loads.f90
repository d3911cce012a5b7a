!> What a step asks of the problem it solves: the external loads on the grid and a prescribed drive.
!> The steppers (the explicit schemes, the fused kernels, the implicit integrators) see only this
!> type; a scene (src/scene) extends it with everything else that is problem-specific. Each load is
!> registered by a flag, so that a step whose problem has none pays nothing for it.
module mpm_loads
   use mpm_kinds, only: dp
   use mpm_grid, only: grid_t, grid_loads_t
   use mpm_particles, only: particles_t
   use mpm_shape, only: shape_cache_t
   implicit none
   private
   public :: loads_t, drive_t

   !> A drive in the form the implicit integrators take it (mpm_implicit): nodes held at the
   !> velocity `velocity`, and a point whose interpolated velocity is prescribed,
   !> sum_k weight(k) v(first + k - 1) = velocity (no point when weight has size 0).
   type :: drive_t
      integer, allocatable :: nodes(:)
      integer :: first = 0
      real(dp), allocatable :: weight(:)
      real(dp) :: velocity = 0.0_dp
   end type drive_t

   !> The loads of a problem. The defaults: no load at all.
   type :: loads_t
      !> Whether the problem adds external (body or driving) forces to the grid each step.
      logical :: external_forces = .false.
      !> Whether its external forces differ between particles and are given per particle by
      !> particle_forces (the fused kernels map them; the generic path's add_forces uses the same values).
      logical :: has_particle_forces = .false.
      !> Whether the problem drives its body at a prescribed velocity: its add_forces is then the explicit
      !> schemes' drive, and the implicit integrators take `drive` instead.
      logical :: drives = .false.
   contains
      !> The external forces that are grid operations (a uniform body acceleration, a driven node:
      !> mpm_grid's grid_loads_t), for the fused kernels' path (default: none).
      procedure :: grid_loads
      !> External forces per particle at time t (N per unit area; called only when has_particle_forces).
      procedure :: particle_forces
      !> External nodal forces at time t, added to grid%force (called only when external_forces), from the
      !> nodal masses or, for forces that differ between particles, through the step's shape functions.
      procedure :: add_forces
      !> The drive as the implicit integrators take it (when `drives`), at the start of a step.
      procedure :: drive
   end type loads_t

contains

   !> No external force (problems that have some override this and set external_forces).
   subroutine add_forces(self, grid, t, cache, particles)
      class(loads_t), intent(in) :: self
      type(grid_t), intent(inout) :: grid
      real(dp), intent(in) :: t
      type(shape_cache_t), intent(in) :: cache
      type(particles_t), intent(in) :: particles
   end subroutine add_forces

   !> No grid loads. Every field is set here (and in the scenes' versions): the default initialisation
   !> of a function result was not applied in a -march=native build of gfortran 12 (the benchmark's
   !> bar read driven_node = 0 and drive_dt = 0, dividing by zero).
   pure function grid_loads(self) result(loads)
      class(loads_t), intent(in) :: self
      type(grid_loads_t) :: loads
      loads = grid_loads_t(acceleration=0.0_dp, driven_node=-1, drive_velocity=0.0_dp, drive_dt=1.0_dp)
   end function grid_loads

   !> No per-particle force (problems that have some override this and set has_particle_forces).
   subroutine particle_forces(self, t, particles, forces)
      class(loads_t), intent(in) :: self
      real(dp), intent(in) :: t
      type(particles_t), intent(in) :: particles
      real(dp), intent(out), contiguous :: forces(:)
      forces = 0.0_dp
   end subroutine particle_forces

   !> No drive (problems that drive their body override this and set `drives`).
   subroutine drive(self, grid, cache, particles, driven)
      class(loads_t), intent(in) :: self
      type(grid_t), intent(in) :: grid
      type(shape_cache_t), intent(in) :: cache
      type(particles_t), intent(in) :: particles
      type(drive_t), intent(out) :: driven
      allocate (driven%nodes(0), driven%weight(0))
   end subroutine drive
end module mpm_loads
