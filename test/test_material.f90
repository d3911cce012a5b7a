!> The elastic material against its closed forms: a constant strain rate applied in n increments
!> gives sigma = E n d eps exactly (the stress is linear in the increments) and J = (1 + d eps)^n; in
!> the continuum the law is sigma = E ln F (1-D: J = F), which the increments approach as d eps -> 0
!> with the error E n d eps^2 / 2 of ln(1 + d eps) ~ d eps - d eps^2/2. Stored energy sigma^2 V/(2E).
program test_material
   use mpm_kinds, only: dp
   use mpm_material_elastic, only: elastic_update, strain_energy_density
   use mpm_testing, only: tester_t
   implicit none
   type(tester_t) :: t
   real(dp), parameter :: youngs = 3.0e9_dp, total = 0.02_dp
   real(dp) :: stress, jac, de, previous
   integer :: n, k, steps
   t%name = 'test_material'
   previous = huge(1.0_dp)
   do k = 1, 4
      steps = 10**k
      de = total/steps
      stress = 0.0_dp
      jac = 1.0_dp
      do n = 1, steps
         call elastic_update(youngs, de, stress, jac)
      end do
      call t%check_close('stress after n increments = E n d eps', stress, youngs*total, rtol=1.0e-12_dp)
      call t%check_close('J = (1 + d eps)^n', jac, (1.0_dp + de)**steps, rtol=1.0e-12_dp)
      call t%check_close('sigma -> E ln F: difference E n d eps^2/2', stress - youngs*log(jac), &
                         youngs*steps*de**2/2, rtol=0.01_dp)
      call t%check('converges to E ln F as d eps -> 0', abs(stress - youngs*log(jac)) < previous)
      previous = abs(stress - youngs*log(jac))
   end do
   call t%check_close('strain energy sigma^2 V / (2E)', strain_energy_density(youngs, 6.0e6_dp, 0.5_dp), &
                      (6.0e6_dp)**2*0.5_dp/(2*youngs), rtol=1.0e-15_dp)
   call t%finish()
end program test_material
