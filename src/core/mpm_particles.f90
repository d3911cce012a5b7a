!> Material points as a structure of arrays. On the fused path all particles of a run share one mass
!> and one initial volume (they fill equal sub-cells of equal elements), so those are scalars: the bar
!> carries only what it needs (44 bytes per particle). The generic path keeps them per particle
!> (`mass_of`, `volume0_of`, allocated by `per_particle_data` only there: 60 bytes per particle), as
!> bodies of several materials or particle sizes need.
module mpm_particles
   use mpm_kinds, only: dp, i8
   use mpm_errors, only: error_t, set_error
   use mpm_strings, only: str
   use mpm_state, only: state_t
   implicit none
   private
   public :: particles_t, particles_init, bytes_per_particle, per_particle_data, permute, sync_particles

   !> Storage per particle: x, x0, v, stress, volume_ratio (8 bytes each) and cell (4 bytes).
   integer, parameter :: bytes_per_particle = 5*8 + 4

   type :: particles_t
      integer :: count = 0
      !> Mass and initial volume of every particle (kg per unit area, m^3 per unit area).
      real(dp) :: mass = 0.0_dp
      real(dp) :: volume0 = 0.0_dp
      real(dp), allocatable :: x(:)            !< position (m)
      real(dp), allocatable :: x0(:)           !< initial position X (m), for u = x - X
      real(dp), allocatable :: v(:)            !< velocity (m/s)
      real(dp), allocatable :: stress(:)       !< Cauchy stress (Pa)
      real(dp), allocatable :: volume_ratio(:) !< J = V/V0
      integer, allocatable :: cell(:)          !< element holding the particle at the start of the step
      real(dp), allocatable :: mass_of(:)      !< per-particle mass (generic path only)
      real(dp), allocatable :: volume0_of(:)   !< per-particle initial volume (generic path only)
      real(dp), allocatable :: velocity_gradient(:) !< dv/dx carried by APIC (transfer = 'apic' only; 1/s)
      !> per-particle Young's modulus (Pa): only scenes of several materials allocate it (composite bar);
      !> otherwise the run's one modulus applies
      real(dp), allocatable :: youngs_modulus_of(:)
      !> the body each particle belongs to (1, 2, ...): only scenes of several bodies allocate it (impact),
      !> which place each body's particles as one contiguous range
      integer, allocatable :: body(:)
      !> per-particle columns a layer above attaches to the particles (one column each), permuted with them:
      !> values computed once from the particles' initial state that a later pass reads (a scene's factors:
      !> the manufactured solution's A sin kX and A k cos kX); allocated only by a layer that attaches some
      real(dp), allocatable :: attached(:, :)
      !> the elastoplastic law's state (mpm_material_plastic), allocated only when a body is elastoplastic:
      !> plastic strain eps_p and hardening variable alpha (the accumulated |d eps_p|)
      real(dp), allocatable :: plastic_strain(:), hardening(:)
      !> per-particle yield stress and hardening modulus (Pa): only elastoplastic scenes of several
      !> materials allocate them (composite bar, impact); otherwise the run's one material applies
      real(dp), allocatable :: yield_stress_of(:), hardening_modulus_of(:)
   end type particles_t

contains

   !> Place `per_element` particles at the centres of equal sub-cells of each of `elements`
   !> elements of size dx, at rest, unstressed; mass density*dx/per_element each.
   subroutine particles_init(particles, elements, per_element, dx, density, error)
      type(particles_t), intent(out) :: particles
      integer, intent(in) :: elements, per_element
      real(dp), intent(in) :: dx, density
      type(error_t), allocatable, intent(out) :: error
      integer :: e, k, p, stat
      real(dp) :: sub
      particles%count = elements*per_element
      allocate (particles%x(particles%count), particles%x0(particles%count), particles%v(particles%count), &
                particles%stress(particles%count), &
                particles%volume_ratio(particles%count), particles%cell(particles%count), stat=stat)
      if (stat /= 0) then
         call set_error(error, "cannot allocate "//str(int(elements, i8)*per_element)//" particles ("// &
                        str(int(elements, i8)*per_element*bytes_per_particle)//" bytes; out of memory)")
         return
      end if
      sub = dx/per_element
      particles%volume0 = sub
      particles%mass = density*sub
      do e = 1, elements
         do k = 1, per_element
            p = (e - 1)*per_element + k
            particles%x(p) = (e - 1)*dx + (k - 0.5_dp)*sub
            particles%cell(p) = e
         end do
      end do
      particles%x0 = particles%x
      particles%v = 0.0_dp
      particles%stress = 0.0_dp
      particles%volume_ratio = 1.0_dp
   end subroutine particles_init

   !> Per-particle mass and initial volume from the shared ones (the generic path reads only these),
   !> unless the scene has set them already (bodies of several materials).
   subroutine per_particle_data(particles, error)
      type(particles_t), intent(inout) :: particles
      type(error_t), allocatable, intent(out) :: error
      integer :: stat
      if (allocated(particles%mass_of) .and. allocated(particles%volume0_of)) return
      allocate (particles%mass_of(particles%count), particles%volume0_of(particles%count), stat=stat)
      if (stat /= 0) then
         call set_error(error, "cannot allocate per-particle data for "//str(particles%count)//" particles (out of memory)")
         return
      end if
      particles%mass_of = particles%mass
      particles%volume0_of = particles%volume0
   end subroutine per_particle_data

   !> Reorder every particle array that is allocated: new index of particle p = destination(p).
   !> The one place that knows the particle fields, so a sort cannot forget one.
   subroutine permute(particles, destination)
      type(particles_t), intent(inout) :: particles
      integer, intent(in) :: destination(:)
      call permute_real(particles%x)
      call permute_real(particles%x0)
      call permute_real(particles%v)
      call permute_real(particles%stress)
      call permute_real(particles%volume_ratio)
      call permute_real(particles%mass_of)
      call permute_real(particles%volume0_of)
      call permute_real(particles%velocity_gradient)
      call permute_real(particles%youngs_modulus_of)
      call permute_real(particles%plastic_strain)
      call permute_real(particles%hardening)
      call permute_real(particles%yield_stress_of)
      call permute_real(particles%hardening_modulus_of)
      call permute_int(particles%body)
      call permute_int(particles%cell)
      if (allocated(particles%attached)) then
         block
            real(dp), allocatable :: copy(:, :)
            allocate (copy(size(particles%attached, 1), size(particles%attached, 2)))
            copy(destination, :) = particles%attached
            call move_alloc(copy, particles%attached)
         end block
      end if
   contains
      subroutine permute_real(a)
         real(dp), allocatable, intent(inout) :: a(:)
         real(dp), allocatable :: copy(:)
         if (.not. allocated(a)) return
         allocate (copy(size(a)))
         copy(destination) = a
         call move_alloc(copy, a)
      end subroutine permute_real
      subroutine permute_int(a)
         integer, allocatable, intent(inout) :: a(:)
         integer, allocatable :: copy(:)
         if (.not. allocated(a)) return
         allocate (copy(size(a)))
         copy(destination) = a
         call move_alloc(copy, a)
      end subroutine permute_int
   end subroutine permute

   !> The particles to or from `state` (under particles.*, as state%saving says), for a checkpoint.
   subroutine sync_particles(state, particles)
      type(state_t), intent(inout) :: state
      type(particles_t), intent(inout) :: particles
      call state%sync('particles.count', particles%count)
      call state%sync('particles.mass', particles%mass)
      call state%sync('particles.volume0', particles%volume0)
      call state%sync('particles.x', particles%x)
      call state%sync('particles.x0', particles%x0)
      call state%sync('particles.v', particles%v)
      call state%sync('particles.stress', particles%stress)
      call state%sync('particles.volume_ratio', particles%volume_ratio)
      call state%sync('particles.cell', particles%cell)
      call state%sync('particles.mass_of', particles%mass_of)
      call state%sync('particles.volume0_of', particles%volume0_of)
      call state%sync('particles.velocity_gradient', particles%velocity_gradient)
      call state%sync('particles.youngs_modulus_of', particles%youngs_modulus_of)
      call state%sync('particles.body', particles%body)
      call state%sync('particles.attached', particles%attached)
      call state%sync('particles.plastic_strain', particles%plastic_strain)
      call state%sync('particles.hardening', particles%hardening)
      call state%sync('particles.yield_stress_of', particles%yield_stress_of)
      call state%sync('particles.hardening_modulus_of', particles%hardening_modulus_of)
   end subroutine sync_particles
end module mpm_particles
