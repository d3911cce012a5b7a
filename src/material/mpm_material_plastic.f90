!> The elastoplastic law: Hencky elasticity (the rate form of mpm_material_elastic, d sigma = E d eps,
!> J <- J (1 + d eps)) with linear isotropic hardening in 1-D, integrated by the return mapping of
!> Simo and Hughes, Computational Inelasticity (Springer 1998, ISBN 978-0-387-97520-7,
!> doi:10.1007/b98904), sec. 1.4 (Box 1.4, one-dimensional rate-independent plasticity):
!>   trial   sigma_tr = sigma_n + E d eps            (the hencky update: a law that never yields is hencky)
!>   yield   f_tr = |sigma_tr| - (sigma_y + H alpha_n)
!>   elastic f_tr <= 0: sigma = sigma_tr
!>   return  f_tr > 0:  d gamma = f_tr/(E + H), sigma = sigma_tr - E d gamma sign(sigma_tr),
!>           eps_p += d gamma sign(sigma_tr), alpha += d gamma
!> so that afterwards |sigma| = sigma_y + H alpha (the yield condition holds). The consistent tangent
!> d sigma/d eps is E in an elastic step and E H/(E + H) in a plastic one (Simo and Hughes, eq. 1.4.29).
!> Energies: the stored elastic energy is the Hencky law's sigma^2 V/(2E); the plastic work per unit
!> reference volume, int sigma d eps_p = int (sigma_y + H alpha) d alpha, is a function of the state,
!> sigma_y alpha + H alpha^2/2: sigma_y alpha is dissipated, H alpha^2/2 stored in the hardening.
module mpm_material_plastic
   use mpm_kinds, only: dp
   implicit none
   private
   public :: radial_return, plastic_tangent, plastic_work_density, dissipation_density, plastic_update_all
   public :: hardening_tangent

contains

   !> One particle's step: the hencky trial stress and the return to the yield surface (see the module).
   elemental subroutine radial_return(youngs_modulus, yield_stress, hardening_modulus, dstrain, stress, &
                                      plastic_strain, hardening)
      real(dp), intent(in) :: youngs_modulus, yield_stress, hardening_modulus, dstrain
      real(dp), intent(inout) :: stress, plastic_strain, hardening
      call return_step(youngs_modulus, yield_stress, hardening_modulus, dstrain, stress, plastic_strain, hardening)
   end subroutine radial_return

   !> radial_return's body, private so that the loops here inline it (a public procedure of a library
   !> built with -fPIC may be interposed, and gfortran then calls it per particle).
   elemental subroutine return_step(youngs_modulus, yield_stress, hardening_modulus, dstrain, stress, &
                                    plastic_strain, hardening)
      real(dp), intent(in) :: youngs_modulus, yield_stress, hardening_modulus, dstrain
      real(dp), intent(inout) :: stress, plastic_strain, hardening
      real(dp) :: increment
      stress = stress + youngs_modulus*dstrain
      ! d gamma, zero in an elastic step: written without a branch, so that a loop over particles
      ! vectorises; an elastic step then subtracts and adds zeros, which leaves the hencky bits
      increment = max(abs(stress) - (yield_stress + hardening_modulus*hardening), 0.0_dp)/ &
                  (youngs_modulus + hardening_modulus)
      stress = stress - sign(youngs_modulus*increment, stress)
      plastic_strain = plastic_strain + sign(increment, stress)
      hardening = hardening + increment
   end subroutine return_step

   !> The consistent tangent d sigma_{n+1}/d (d eps) of radial_return from the state before the step:
   !> E when the trial stress stays within the yield surface, E H/(E + H) when it returns.
   elemental real(dp) function plastic_tangent(youngs_modulus, yield_stress, hardening_modulus, dstrain, stress, &
                                               hardening) result(tangent)
      real(dp), intent(in) :: youngs_modulus, yield_stress, hardening_modulus, dstrain, stress, hardening
      if (abs(stress + youngs_modulus*dstrain) - (yield_stress + hardening_modulus*hardening) > 0.0_dp) then
         tangent = hardening_tangent(youngs_modulus, hardening_modulus)
      else
         tangent = youngs_modulus
      end if
   end function plastic_tangent

   !> The tangent modulus of plastic loading, E_t = E H/(E + H) (0 when H = 0), formed as written while
   !> E H is a double and as min/(1 + min/max) of E and H beyond (E = 2e11 and H = 1e300: E_t = E, where
   !> E H overflowed to a NaN tangent).
   elemental real(dp) function hardening_tangent(youngs_modulus, hardening_modulus) result(tangent)
      real(dp), intent(in) :: youngs_modulus, hardening_modulus
      real(dp) :: product
      product = youngs_modulus*hardening_modulus
      if (product <= huge(1.0_dp)) then
         tangent = product/(youngs_modulus + hardening_modulus)
      else
         tangent = min(youngs_modulus, hardening_modulus)/(1.0_dp + min(youngs_modulus, hardening_modulus)/ &
                                                           max(youngs_modulus, hardening_modulus))
      end if
   end function hardening_tangent

   !> Plastic work of a particle, (sigma_y alpha + H alpha^2/2) V0.
   elemental real(dp) function plastic_work_density(yield_stress, hardening_modulus, hardening, volume0)
      real(dp), intent(in) :: yield_stress, hardening_modulus, hardening, volume0
      plastic_work_density = work_of(yield_stress, hardening_modulus, hardening, volume0)
   end function plastic_work_density

   !> plastic_work_density's body, private (inlined in the loops; see return_step).
   elemental real(dp) function work_of(yield_stress, hardening_modulus, hardening, volume0)
      real(dp), intent(in) :: yield_stress, hardening_modulus, hardening, volume0
      work_of = (yield_stress + 0.5_dp*hardening_modulus*hardening)*hardening*volume0
   end function work_of

   !> The dissipated part of it, sigma_y alpha V0 (the rest, H alpha^2 V0/2, is stored in the hardening).
   elemental real(dp) function dissipation_density(yield_stress, hardening, volume0)
      real(dp), intent(in) :: yield_stress, hardening, volume0
      dissipation_density = yield_stress*hardening*volume0
   end function dissipation_density

   !> radial_return of every particle and J <- J (1 + d eps), in one loop; returns the elastic energy
   !> sum sigma^2 J V0/(2E) (written as the hencky updates write it: a law that never yields gives their
   !> bits), the smallest J and the plastic work sum (sigma_y alpha + H alpha^2/2) V0. The material
   !> parameters are given per particle (size of dstrain) or once for all (size 1).
   subroutine plastic_update_all(youngs_modulus, yield_stress, hardening_modulus, dstrain, volume0, stress, &
                                 volume_ratio, plastic_strain, hardening, energy, smallest, work)
      real(dp), intent(in), contiguous :: youngs_modulus(:), yield_stress(:), hardening_modulus(:)
      real(dp), intent(in), contiguous :: dstrain(:), volume0(:)
      real(dp), intent(inout), contiguous :: stress(:), volume_ratio(:), plastic_strain(:), hardening(:)
      real(dp), intent(out) :: energy, smallest, work
      integer :: p
      real(dp) :: half_compliance
      energy = 0.0_dp
      smallest = huge(1.0_dp)
      work = 0.0_dp
      if (size(youngs_modulus) == 1) then
         half_compliance = 0.5_dp/youngs_modulus(1)
         do p = 1, size(dstrain)
            call return_step(youngs_modulus(1), yield_stress(1), hardening_modulus(1), dstrain(p), stress(p), &
                               plastic_strain(p), hardening(p))
            volume_ratio(p) = volume_ratio(p)*(1.0_dp + dstrain(p))
            energy = energy + stress(p)*stress(p)*volume_ratio(p)*volume0(p)*half_compliance
            smallest = min(smallest, volume_ratio(p))
            work = work + work_of(yield_stress(1), hardening_modulus(1), hardening(p), volume0(p))
         end do
      else
         do p = 1, size(dstrain)
            call return_step(youngs_modulus(p), yield_stress(p), hardening_modulus(p), dstrain(p), &
                               stress(p), plastic_strain(p), hardening(p))
            volume_ratio(p) = volume_ratio(p)*(1.0_dp + dstrain(p))
            energy = energy + 0.5_dp*stress(p)*stress(p)*volume_ratio(p)*volume0(p)/youngs_modulus(p)
            smallest = min(smallest, volume_ratio(p))
            work = work + work_of(yield_stress(p), hardening_modulus(p), hardening(p), volume0(p))
         end do
      end if
   end subroutine plastic_update_all
end module mpm_material_plastic
