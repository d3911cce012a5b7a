!> Linear-elastic material in small strain increments: d(sigma) = E d(epsilon); the volume ratio
!> J = V/V0 follows the same increment, J <- J (1 + d(epsilon)).
module mpm_material
   use mpm_kinds, only: dp
   implicit none
   private
   public :: elastic_update, strain_energy_density

contains

   !> Apply the strain increment `dstrain` to stress and volume ratio.
   elemental subroutine elastic_update(youngs_modulus, dstrain, stress, volume_ratio)
      real(dp), intent(in) :: youngs_modulus, dstrain
      real(dp), intent(inout) :: stress, volume_ratio
      stress = stress + youngs_modulus*dstrain
      volume_ratio = volume_ratio*(1.0_dp + dstrain)
   end subroutine elastic_update

   !> Strain energy of a particle: sigma^2 V / (2E).
   elemental real(dp) function strain_energy_density(youngs_modulus, stress, volume)
      real(dp), intent(in) :: youngs_modulus, stress, volume
      strain_energy_density = 0.5_dp*stress*stress*volume/youngs_modulus
   end function strain_energy_density
end module mpm_material
