!> The elastic material against its closed forms: a constant strain rate applied in n increments
!> gives sigma = E n d eps exactly (the stress is linear in the increments) and J = (1 + d eps)^n; in
!> the continuum the law is sigma = E ln F (1-D: J = F), which the increments approach as d eps -> 0
!> with the error E n d eps^2 / 2 of ln(1 + d eps) ~ d eps - d eps^2/2. Stored energy sigma^2 V/(2E).
program test_material
   use mpm_kinds, only: dp
   use mpm_material_elastic, only: elastic_update, strain_energy_density, elastic_update_all
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
   ! the whole-array update (the generic path's) against the per-particle one and the energy formula
   block
      real(dp) :: ds(5), v0(5), s1(5), j1(5), s2(5), j2(5), energy, smallest
      ds = [1.0e-3_dp, -2.0e-3_dp, 0.0_dp, 5.0e-4_dp, -1.0e-4_dp]
      v0 = [1.0_dp, 2.0_dp, 0.5_dp, 1.5_dp, 3.0_dp]
      s1 = [1.0e6_dp, -2.0e6_dp, 0.0_dp, 3.0e5_dp, 7.0e6_dp]
      j1 = [1.0_dp, 0.99_dp, 1.01_dp, 0.98_dp, 1.02_dp]
      s2 = s1
      j2 = j1
      call elastic_update(youngs, ds, s1, j1)
      call elastic_update_all(youngs, ds, v0, s2, j2, energy, smallest)
      call t%check('elastic_update_all = elastic_update per particle', all(s1 == s2) .and. all(j1 == j2))
      call t%check_close('elastic_update_all energy = sum sigma^2 J V0 / (2E)', energy, &
                         sum(strain_energy_density(youngs, s1, j1*v0)), rtol=1.0e-14_dp)
      call t%check('elastic_update_all smallest J', smallest == minval(j1))
   end block
   call t%finish()
end program test_material
