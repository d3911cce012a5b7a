!> The material layer: the bar's elastic law. Stress rate from the velocity gradient,
!> sigma' = E dv/dx, applied per step as d sigma = E d eps with d eps = dt dv/dx; the volume ratio
!> follows J <- J (1 + d eps). In the continuum (1-D: J = F, dv/dx = F'/F) this is sigma = E ln F,
!> a hypo-elastic law that is linear elasticity at small strain (ln F = eps + O(eps^2)); the paper's
!> exact solution is that of linear elasticity, so the two differ by relative order v0/c at finite
!> amplitude. The stored energy reported is sigma^2 V / (2E), V = J V0 (the small-strain energy).
module mpm_material_elastic
   use mpm_kinds, only: dp
   implicit none
   private
   public :: elastic_update, strain_energy_density, elastic_update_all, elastic_update_each

contains

   !> Apply the strain increment `dstrain` to stress and volume ratio.
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
end module mpm_material_elastic
