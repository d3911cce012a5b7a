!> The elastic laws, as updates of the stress by a strain increment d eps = dt dv/dx (the log-strain
!> increment of a step: in 1-D J = F, dv/dx = F'/F); the volume ratio follows J <- J (1 + d eps).
!> - `hencky`: the stress rate sigma' = E dv/dx applied per step as d sigma = E d eps. In the continuum this
!>   is sigma = E ln F, a hypo-elastic law that is linear elasticity at small strain (ln F = eps + O(eps^2));
!>   the paper's exact solution is that of linear elasticity, so the two differ by relative order v0/c at
!>   finite amplitude. Stored energy reported: sigma^2 V/(2E), V = J V0 (the small-strain energy).
!> - `linear`: sigma = E (J - 1). In 1-D with unit area the first Piola-Kirchhoff stress is the Cauchy
!>   stress, so the momentum balance is exactly rho0 u_tt = E u_XX (linear elasticity at any amplitude):
!>   the paper's exact solution is exact for it, and what error remains is the method's. It is updated
!>   as sigma <- sigma + (E + sigma) d eps, which is E (J (1 + d eps) - 1) for sigma = E (J - 1) without
!>   forming J - 1: at a strain of 2e-7 (the bar at v0 = 0.001 m/s) J - 1 from the product J of 6e4
!>   factors lost 3e-6 of its value to round-off, a floor in the bar's u_cm error at 2e-6 relative.
!>   Stored energy: int sigma dF = E (J - 1)^2/2 per reference volume, sigma^2 V0/(2E), the exact
!>   invariant of the continuum.
!> Each law has an elemental update of one particle (what a fused stress pass calls) and whole-array
!> updates with the energy sum and the smallest J (the generic path's, in one loop so that the compiler
!> sees the law: a call per particle across modules is not inlined), for one Young's modulus (`_all`)
!> or one per particle (`_each`, bodies of several materials).
module mpm_material_elastic
   use mpm_kinds, only: dp
   implicit none
   private
   public :: elastic_update, strain_energy_density, elastic_update_all, elastic_update_each
   public :: linear_update, linear_energy_density, linear_update_all, linear_update_each, &
             linear_update_on, linear_update_each_on

contains

   !> Apply the strain increment `dstrain` to stress and volume ratio (hencky).
   elemental subroutine elastic_update(youngs_modulus, dstrain, stress, volume_ratio)
      real(dp), intent(in) :: youngs_modulus, dstrain
      real(dp), intent(inout) :: stress, volume_ratio
      stress = stress + youngs_modulus*dstrain
      volume_ratio = volume_ratio*(1.0_dp + dstrain)
   end subroutine elastic_update

   !> elastic_update of every particle with its strain increment, in one loop (here, so that the
   !> compiler sees the law: a call per particle across modules is not inlined); returns the total
   !> strain energy sum sigma^2 J V0 / (2E) and the smallest J.
   subroutine elastic_update_all(youngs_modulus, dstrain, volume0, stress, volume_ratio, energy, smallest)
      real(dp), intent(in) :: youngs_modulus
      real(dp), intent(in), contiguous :: dstrain(:), volume0(:)
      real(dp), intent(inout), contiguous :: stress(:), volume_ratio(:)
      real(dp), intent(out) :: energy, smallest
      integer :: p
      real(dp) :: half_compliance
      half_compliance = 0.5_dp/youngs_modulus
      energy = 0.0_dp
      smallest = huge(1.0_dp)
      do p = 1, size(dstrain)
         stress(p) = stress(p) + youngs_modulus*dstrain(p)
         volume_ratio(p) = volume_ratio(p)*(1.0_dp + dstrain(p))
         energy = energy + stress(p)*stress(p)*volume_ratio(p)*volume0(p)*half_compliance
         smallest = min(smallest, volume_ratio(p))
      end do
   end subroutine elastic_update_all

   !> elastic_update_all with a Young's modulus per particle (bodies of several materials).
   subroutine elastic_update_each(youngs_modulus, dstrain, volume0, stress, volume_ratio, energy, smallest)
      real(dp), intent(in), contiguous :: youngs_modulus(:), dstrain(:), volume0(:)
      real(dp), intent(inout), contiguous :: stress(:), volume_ratio(:)
      real(dp), intent(out) :: energy, smallest
      integer :: p
      energy = 0.0_dp
      smallest = huge(1.0_dp)
      do p = 1, size(dstrain)
         stress(p) = stress(p) + youngs_modulus(p)*dstrain(p)
         volume_ratio(p) = volume_ratio(p)*(1.0_dp + dstrain(p))
         energy = energy + 0.5_dp*stress(p)*stress(p)*volume_ratio(p)*volume0(p)/youngs_modulus(p)
         smallest = min(smallest, volume_ratio(p))
      end do
   end subroutine elastic_update_each

   !> Strain energy of a particle: sigma^2 V / (2E).
   elemental real(dp) function strain_energy_density(youngs_modulus, stress, volume)
      real(dp), intent(in) :: youngs_modulus, stress, volume
      strain_energy_density = 0.5_dp*stress*stress*volume/youngs_modulus
   end function strain_energy_density

   !> The linear law for one particle: J <- J (1 + d eps) and sigma <- sigma + (E + sigma) d eps, which
   !> keeps sigma = E (J - 1) (see the module) without the cancellation of J - 1.
   elemental subroutine linear_update(youngs_modulus, dstrain, stress, volume_ratio)
      real(dp), intent(in) :: youngs_modulus, dstrain
      real(dp), intent(inout) :: stress, volume_ratio
      volume_ratio = volume_ratio*(1.0_dp + dstrain)
      stress = stress + (youngs_modulus + stress)*dstrain
   end subroutine linear_update

   !> Stored energy of the linear law, E (J - 1)^2 V0/2 = sigma^2 V0/(2E) (V0: reference volume).
   elemental real(dp) function linear_energy_density(youngs_modulus, stress, volume0)
      real(dp), intent(in) :: youngs_modulus, stress, volume0
      linear_energy_density = 0.5_dp*stress*stress*volume0/youngs_modulus
   end function linear_energy_density

   !> linear_update of every particle; the total stored energy sum sigma^2 V0/(2E) and the smallest J.
   subroutine linear_update_all(youngs_modulus, dstrain, volume0, stress, volume_ratio, energy, smallest)
      real(dp), intent(in) :: youngs_modulus
      real(dp), intent(in), contiguous :: dstrain(:), volume0(:)
      real(dp), intent(inout), contiguous :: stress(:), volume_ratio(:)
      real(dp), intent(out) :: energy, smallest
      energy = 0.0_dp
      smallest = huge(1.0_dp)
      call linear_update_on(youngs_modulus, dstrain, volume0, stress, volume_ratio, energy, smallest)
   end subroutine linear_update_all

   !> linear_update_all on a run of particles whose sums go on: their energies added to `energy` in their
   !> order, `smallest` lowered to their smallest J (a pass that updates its particles block by block
   !> forms the same sums as linear_update_all over all of them).
   subroutine linear_update_on(youngs_modulus, dstrain, volume0, stress, volume_ratio, energy, smallest)
      real(dp), intent(in) :: youngs_modulus
      real(dp), intent(in), contiguous :: dstrain(:), volume0(:)
      real(dp), intent(inout), contiguous :: stress(:), volume_ratio(:)
      real(dp), intent(inout) :: energy, smallest
      integer :: p
      real(dp) :: half_compliance, total, least
      half_compliance = 0.5_dp/youngs_modulus
      total = energy
      least = smallest
      do p = 1, size(dstrain)
         volume_ratio(p) = volume_ratio(p)*(1.0_dp + dstrain(p))
         stress(p) = stress(p) + (youngs_modulus + stress(p))*dstrain(p)
         total = total + stress(p)*stress(p)*volume0(p)*half_compliance
         least = min(least, volume_ratio(p))
      end do
      energy = total
      smallest = least
   end subroutine linear_update_on

   !> linear_update_all with a Young's modulus per particle.
   subroutine linear_update_each(youngs_modulus, dstrain, volume0, stress, volume_ratio, energy, smallest)
      real(dp), intent(in), contiguous :: youngs_modulus(:), dstrain(:), volume0(:)
      real(dp), intent(inout), contiguous :: stress(:), volume_ratio(:)
      real(dp), intent(out) :: energy, smallest
      energy = 0.0_dp
      smallest = huge(1.0_dp)
      call linear_update_each_on(youngs_modulus, dstrain, volume0, stress, volume_ratio, energy, smallest)
   end subroutine linear_update_each

   !> linear_update_each on a run of particles whose sums go on (as linear_update_on).
   subroutine linear_update_each_on(youngs_modulus, dstrain, volume0, stress, volume_ratio, energy, smallest)
      real(dp), intent(in), contiguous :: youngs_modulus(:), dstrain(:), volume0(:)
      real(dp), intent(inout), contiguous :: stress(:), volume_ratio(:)
      real(dp), intent(inout) :: energy, smallest
      integer :: p
      real(dp) :: total, least
      total = energy
      least = smallest
      do p = 1, size(dstrain)
         volume_ratio(p) = volume_ratio(p)*(1.0_dp + dstrain(p))
         stress(p) = stress(p) + (youngs_modulus(p) + stress(p))*dstrain(p)
         total = total + 0.5_dp*stress(p)*stress(p)*volume0(p)/youngs_modulus(p)
         least = min(least, volume_ratio(p))
      end do
      energy = total
      smallest = least
   end subroutine linear_update_each_on
end module mpm_material_elastic
