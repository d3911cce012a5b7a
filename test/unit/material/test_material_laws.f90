!> The material laws against their closed forms.
!> - hencky: a constant strain rate applied in n increments gives sigma = E n d eps exactly (the stress is
!>   linear in the increments) and J = (1 + d eps)^n; in the continuum the law is sigma = E ln F (1-D:
!>   J = F), which the increments approach as d eps -> 0 with the error E n d eps^2 / 2 of
!>   ln(1 + d eps) ~ d eps - d eps^2/2. Stored energy sigma^2 V/(2E).
!> - linear: sigma = E (J - 1) whatever the path of the increments; its stored energy sigma^2 V0/(2E) is
!>   the work int sigma dJ per reference volume (checked by quadrature along a path that goes and returns).
!> - elastoplastic (radial return, Simo and Hughes 1998): elastic below yield (the hencky bits); after a
!>   return |sigma| = sigma_y + H alpha to round-off; monotone loading gives the bilinear curve
!>   sigma = sigma_y + E_t (eps - sigma_y/E), E_t = E H/(E + H), for any increment size; unloading is
!>   elastic; a strain cycle that ends unloaded encloses the area sigma_y alpha + H alpha^2/2 (the plastic
!>   work); a law that never yields (sigma_y = 1e30) gives the hencky update bit for bit.
!> - tangents: d sigma/d (d eps) of every law against central finite differences of its update.
program test_material_laws
   use, intrinsic :: iso_fortran_env, only: real128
   use mpm_kinds, only: dp
   use mpm_material_elastic, only: elastic_update, strain_energy_density, elastic_update_all, linear_update, &
                                   linear_update_all, linear_energy_density
   use mpm_material_plastic, only: radial_return, plastic_update_all, plastic_work_density, dissipation_density, &
                                   hardening_tangent
   use mpm_strings, only: str
   use mpm_material, only: law_hencky, law_linear, law_elastoplastic, law_tangent, law_id, law_name, known_laws
   use mpm_testing, only: tester_t, tester, fixed_seed
   implicit none
   type(tester_t) :: t
   real(dp), parameter :: youngs = 3.0e9_dp, total = 0.02_dp
   real(dp), parameter :: yield = 2.0e6_dp, hardening_modulus = 5.0e7_dp
   t = tester('test_material_laws')
   if (t%case('hencky')) call hencky()
   if (t%case('linear')) call linear()
   if (t%case('elastic_below_yield')) call elastic_below_yield()
   if (t%case('on_the_yield_surface')) call on_the_yield_surface()
   if (t%case('bilinear_curve')) call bilinear_curve()
   if (t%case('elastic_unloading')) call elastic_unloading()
   if (t%case('hysteresis')) call hysteresis()
   if (t%case('never_yielding_is_hencky')) call never_yielding_is_hencky()
   if (t%case('tangents')) call tangents()
   if (t%case('names')) call names()
   call t%finish()

contains

   subroutine hencky()
      real(dp) :: stress, jac, de, previous
      integer :: n, k, steps
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
   end subroutine hencky

   !> sigma = E (J - 1) along any path; the stored energy is the work int sigma dJ (per V0).
   subroutine linear()
      real(dp) :: stress, jac, work, previous_j, previous_s, de
      integer :: n
      stress = 0.0_dp
      jac = 1.0_dp
      work = 0.0_dp
      ! stretch by 30 %, compress to -20 %, back to +5 %: strain increments of varying size and sign
      do n = 1, 3000
         de = 3.0e-4_dp*sin(0.003_dp*n)*(1.0_dp + 0.5_dp*cos(0.05_dp*n))
         previous_j = jac
         previous_s = stress
         call linear_update(youngs, de, stress, jac)
         work = work + 0.5_dp*(stress + previous_s)*(jac - previous_j) ! exact: sigma is linear in J
      end do
      call t%check('linear: J moved far from 1 (the test is at finite strain)', abs(jac - 1.0_dp) > 0.05_dp)
      call t%check_close('linear: sigma = E (J - 1) after a path of increments', stress, youngs*(jac - 1.0_dp), &
                         rtol=1.0e-12_dp)
      call t%check_close('linear: stored energy sigma^2 V0/(2E) = int sigma dJ V0', &
                         linear_energy_density(youngs, stress, 2.0_dp), 2.0_dp*work, rtol=1.0e-9_dp)
      ! at small strain, after many steps: sigma against E (J - 1) with J formed in quadruple precision (the
      ! bar at v0 = 0.001 m/s: strains of 2e-7 over 6.4e4 steps; E (J - 1) from the double J lost 3e-6)
      block
         real(real128) :: jq
         real(dp) :: worst, s, j
         s = 0.0_dp
         j = 1.0_dp
         jq = 1.0_real128
         worst = 0.0_dp
         do n = 1, 64000
            de = 2.0e-7_dp*(sin(6.283185307179586_dp*n/16000) - sin(6.283185307179586_dp*(n - 1)/16000))
            call linear_update(youngs, de, s, j)
            jq = jq*(1.0_real128 + real(de, real128))
            worst = max(worst, abs(s - real(youngs*(jq - 1.0_real128), dp)))
         end do
         call t%check('linear at strain 2e-7 over 64000 steps: sigma = E (J - 1) to 1e-10 of E eps', &
                      worst < 1.0e-10_dp*youngs*2.0e-7_dp, 'worst '//real_text(worst/(youngs*2.0e-7_dp)))
      end block
      block
         real(dp) :: ds(4), v0(4), s1(4), j1(4), s2(4), j2(4), energy, smallest
         ds = [1.0e-3_dp, -2.0e-3_dp, 0.0_dp, 5.0e-4_dp]
         v0 = [1.0_dp, 2.0_dp, 0.5_dp, 1.5_dp]
         s1 = [1.0e6_dp, -2.0e6_dp, 0.0_dp, 3.0e5_dp]
         j1 = [1.0_dp, 0.99_dp, 1.01_dp, 0.98_dp]
         s2 = s1
         j2 = j1
         call linear_update(youngs, ds, s1, j1)
         call linear_update_all(youngs, ds, v0, s2, j2, energy, smallest)
         call t%check('linear_update_all = linear_update per particle', all(s1 == s2) .and. all(j1 == j2))
         call t%check_close('linear_update_all energy = sum sigma^2 V0/(2E)', energy, &
                            sum(s1**2*v0/(2*youngs)), rtol=1.0e-14_dp)
         call t%check('linear_update_all smallest J', smallest == minval(j1))
      end block
   end subroutine linear

   !> Below yield the return mapping is the hencky update, bit for bit, and leaves no plastic state.
   subroutine elastic_below_yield()
      real(dp) :: s1, j1, s2, eps_p, alpha, de
      integer :: n
      s1 = 0.0_dp
      j1 = 1.0_dp
      s2 = 0.0_dp
      eps_p = 0.0_dp
      alpha = 0.0_dp
      do n = 1, 100  ! up to 0.9 sigma_y and back down to -0.9 sigma_y
         de = merge(0.9_dp, -1.8_dp, n <= 50)*yield/youngs/50
         call elastic_update(youngs, de, s1, j1)
         call radial_return(youngs, yield, hardening_modulus, de, s2, eps_p, alpha)
      end do
      call t%check('below yield: the hencky stress bit for bit', s1 == s2, 'sigma '//real_text(s2))
      call t%check('below yield: no plastic strain, no hardening', eps_p == 0.0_dp .and. alpha == 0.0_dp)
   end subroutine elastic_below_yield

   !> From random states on the yield surface or inside it, random increments: after a return the stress
   !> is on the (hardened) yield surface, |sigma| = sigma_y + H alpha, to round-off.
   subroutine on_the_yield_surface()
      real(dp) :: r(3), stress, eps_p, alpha, before, worst
      integer :: n, returns
      call fixed_seed()
      worst = 0.0_dp
      returns = 0
      do n = 1, 2000
         call random_number(r)
         alpha = 0.05_dp*r(1)
         stress = (2*r(2) - 1)*(yield + hardening_modulus*alpha)
         eps_p = 0.0_dp
         before = alpha
         call radial_return(youngs, yield, hardening_modulus, 4.0_dp*(2*r(3) - 1)*yield/youngs, stress, eps_p, alpha)
         if (alpha > before) then
            returns = returns + 1
            worst = max(worst, abs(abs(stress) - (yield + hardening_modulus*alpha))/yield)
            if (abs(eps_p - sign(alpha - before, stress)) > 1.0e-15_dp*alpha) worst = huge(1.0_dp)
         else
            worst = max(worst, max(abs(stress) - (yield + hardening_modulus*alpha), 0.0_dp)/yield)
         end if
      end do
      call t%check('returns happened (a third to two thirds of the draws)', returns > 600 .and. returns < 1400)
      call t%check('|sigma| = sigma_y + H alpha after every return (and never outside the surface); '// &
                   'd eps_p = sign(sigma) d alpha', worst < 4.0e-15_dp, 'worst '//real_text(worst))
   end subroutine on_the_yield_surface

   !> Monotone loading, with increments of any size, lands on the bilinear curve.
   subroutine bilinear_curve()
      real(dp) :: stress, eps_p, alpha, strain, worst, tangent, expected
      integer :: n, k, steps(3)
      tangent = youngs*hardening_modulus/(youngs + hardening_modulus)
      steps = [3, 17, 400]
      worst = 0.0_dp
      do k = 1, size(steps)
         stress = 0.0_dp
         eps_p = 0.0_dp
         alpha = 0.0_dp
         do n = 1, steps(k)
            call radial_return(youngs, yield, hardening_modulus, -10.0_dp*yield/youngs/steps(k), stress, eps_p, alpha)
            strain = -10.0_dp*yield/youngs*n/steps(k)
            if (abs(strain) <= yield/youngs) then
               expected = youngs*strain
            else
               expected = -(yield + tangent*(abs(strain) - yield/youngs))
            end if
            worst = max(worst, abs(stress - expected)/yield)
         end do
      end do
      call t%check('monotone compression: sigma = sigma_y + E_t (eps - eps_y), E_t = E H/(E + H), with 3, 17 '// &
                   'or 400 increments', worst < 1.0e-12_dp, 'worst '//real_text(worst))
      call t%check_close('elastic and plastic parts: eps = sigma/E + eps_p', stress/youngs + eps_p, &
                         -10.0_dp*yield/youngs, rtol=1.0e-12_dp)
   end subroutine bilinear_curve

   !> After plastic loading, a reversal is elastic (d sigma = E d eps, no change of alpha) until the
   !> reversed yield stress -(sigma_y + H alpha) is reached.
   subroutine elastic_unloading()
      real(dp) :: stress, eps_p, alpha, peak, alpha_peak, before
      integer :: n
      logical :: elastic
      stress = 0.0_dp
      eps_p = 0.0_dp
      alpha = 0.0_dp
      call radial_return(youngs, yield, hardening_modulus, 5.0_dp*yield/youngs, stress, eps_p, alpha)
      peak = stress
      alpha_peak = alpha
      elastic = .true.
      do n = 1, 19  ! unload by 1.9 (sigma_y + H alpha): within the elastic range
         before = stress
         call radial_return(youngs, yield, hardening_modulus, -0.1_dp*peak/youngs, stress, eps_p, alpha)
         elastic = elastic .and. abs(stress - before + 0.1_dp*peak) < 1.0e-9_dp*yield .and. alpha == alpha_peak
      end do
      call t%check('unloading is elastic: d sigma = E d eps, alpha unchanged', elastic)
      call radial_return(youngs, yield, hardening_modulus, -0.2_dp*peak/youngs, stress, eps_p, alpha)
      call t%check('reverse yielding at -(sigma_y + H alpha) (isotropic hardening)', alpha > alpha_peak .and. &
                   abs(stress + yield + hardening_modulus*alpha) < 1.0e-12_dp*yield)
   end subroutine elastic_unloading

   !> Tension to 4 eps_y, compression to -3 eps_y, back to sigma = 0 in 10^4 small increments: the area
   !> int sigma d eps (trapezoids) equals the plastic work sigma_y alpha + H alpha^2/2 (the elastic energy
   !> is zero at both ends), of which sigma_y alpha is dissipated.
   subroutine hysteresis()
      real(dp) :: stress, eps_p, alpha, area, previous, strain, target, de
      integer :: leg, n
      real(dp), parameter :: legs(2) = [4.0_dp, -3.0_dp]
      stress = 0.0_dp
      eps_p = 0.0_dp
      alpha = 0.0_dp
      area = 0.0_dp
      strain = 0.0_dp
      do leg = 1, 2
         target = legs(leg)*yield/youngs
         de = (target - strain)/5000
         do n = 1, 5000
            previous = stress
            call radial_return(youngs, yield, hardening_modulus, de, stress, eps_p, alpha)
            area = area + 0.5_dp*(previous + stress)*de
         end do
         strain = target
      end do
      de = -stress/youngs  ! the elastic unloading to sigma = 0
      previous = stress
      call radial_return(youngs, yield, hardening_modulus, de, stress, eps_p, alpha)
      area = area + 0.5_dp*(previous + stress)*de
      call t%check('the cycle ends unloaded', abs(stress) < 1.0e-9_dp*yield)
      call t%check_close('hysteresis area = plastic work sigma_y alpha + H alpha^2/2', area, &
                         plastic_work_density(yield, hardening_modulus, alpha, 1.0_dp), rtol=1.0e-6_dp)
      call t%check_close('dissipated sigma_y alpha', dissipation_density(yield, alpha, 1.0_dp), yield*alpha, &
                         rtol=1.0e-15_dp)
      call t%check('alpha = accumulated |d eps_p| (the loop yielded both ways)', alpha > 5.0_dp*yield/youngs*0.9_dp)
   end subroutine hysteresis

   !> plastic_update_all with sigma_y = 1e30 gives elastic_update_all's stresses, J and energy bit for bit;
   !> with yielding it agrees with radial_return per particle and sums the plastic work (one and several
   !> materials).
   subroutine never_yielding_is_hencky()
      real(dp) :: ds(6), v0(6), s1(6), j1(6), s2(6), j2(6), ep(6), al(6), e1, e2, m1, m2, work
      ds = [1.0e-3_dp, -2.0e-3_dp, 0.0_dp, 5.0e-4_dp, -1.0e-4_dp, 3.0e-3_dp]
      v0 = [1.0_dp, 2.0_dp, 0.5_dp, 1.5_dp, 3.0_dp, 0.7_dp]
      s1 = [1.0e6_dp, -2.0e6_dp, 0.0_dp, 3.0e5_dp, 7.0e6_dp, -1.5e6_dp]
      j1 = [1.0_dp, 0.99_dp, 1.01_dp, 0.98_dp, 1.02_dp, 1.0_dp]
      s2 = s1
      j2 = j1
      ep = 0.0_dp
      al = 0.0_dp
      call elastic_update_all(youngs, ds, v0, s1, j1, e1, m1)
      call plastic_update_all([youngs], [1.0e30_dp], [hardening_modulus], ds, v0, s2, j2, ep, al, e2, m2, work)
      call t%check('sigma_y = 1e30: stresses, J, energy and smallest J of hencky bit for bit', &
                   all(s1 == s2) .and. all(j1 == j2) .and. e1 == e2 .and. m1 == m2 .and. work == 0.0_dp)
      block
         real(dp) :: s3(6), ep3(6), al3(6), j3(6), e3, m3
         s2 = [1.0e6_dp, -2.0e6_dp, 0.0_dp, 3.0e5_dp, 7.0e6_dp, -1.5e6_dp]
         j2 = 1.0_dp
         s3 = s2
         ep = 0.0_dp
         al = [0.0_dp, 1.0e-3_dp, 0.0_dp, 0.0_dp, 2.0e-2_dp, 0.0_dp]
         ep3 = ep
         al3 = al
         j3 = j2
         call radial_return(youngs, yield, hardening_modulus, ds, s3, ep3, al3)
         call plastic_update_all(spread(youngs, 1, 6), spread(yield, 1, 6), spread(hardening_modulus, 1, 6), ds, v0, &
                                 s2, j2, ep, al, e3, m3, work)
         call t%check('plastic_update_all (per particle) = radial_return', all(s2 == s3) .and. all(ep == ep3) .and. &
                      all(al == al3) .and. count(al > 0.0_dp) >= 3)
         call t%check_close('plastic_update_all plastic work = sum (sigma_y alpha + H alpha^2/2) V0', work, &
                            sum((yield + 0.5_dp*hardening_modulus*al)*al*v0), rtol=1.0e-14_dp)
      end block
   end subroutine never_yielding_is_hencky

   !> d sigma/d (d eps) of each law against central differences of its update, from states and
   !> increments away from the yield kink: hencky E, linear E J, elastoplastic E (elastic step) and
   !> E H/(E + H) (plastic step).
   subroutine tangents()
      real(dp), parameter :: h = 1.0e-7_dp
      real(dp) :: stress, jac, de, fd, alpha
      ! hencky
      call t%check_close('hencky tangent = finite difference', &
                         law_tangent(law_hencky, youngs, 0.0_dp, 0.0_dp, 1.0e-3_dp, 1.0e6_dp, 0.97_dp, 0.0_dp), &
                         fd_hencky(1.0e-3_dp, h), rtol=1.0e-7_dp)
      ! linear, at J = 1.3
      jac = 1.3_dp
      de = -2.0e-3_dp
      fd = (linear_after(de + h, jac) - linear_after(de - h, jac))/(2*h)
      call t%check_close('linear tangent E J = finite difference', &
                         law_tangent(law_linear, youngs, 0.0_dp, 0.0_dp, de, 0.0_dp, jac, 0.0_dp), fd, rtol=1.0e-7_dp)
      ! elastoplastic: an elastic step from inside the surface, then a plastic one beyond it
      stress = 0.2_dp*yield
      alpha = 1.0e-3_dp
      de = 0.3_dp*yield/youngs
      fd = (plastic_after(de + h*yield/youngs, stress, alpha) - &
            plastic_after(de - h*yield/youngs, stress, alpha))/(2*h*yield/youngs)
      call t%check_close('elastoplastic tangent, elastic step = E = finite difference', &
                         law_tangent(law_elastoplastic, youngs, yield, hardening_modulus, de, stress, 1.0_dp, alpha), &
                         fd, rtol=1.0e-6_dp)
      call t%check_close('... = E', fd, youngs, rtol=1.0e-6_dp)
      de = 3.0_dp*yield/youngs
      fd = (plastic_after(de + h*yield/youngs, stress, alpha) - &
            plastic_after(de - h*yield/youngs, stress, alpha))/(2*h*yield/youngs)
      call t%check_close('elastoplastic consistent tangent, plastic step = finite difference', &
                         law_tangent(law_elastoplastic, youngs, yield, hardening_modulus, de, stress, 1.0_dp, alpha), &
                         fd, rtol=1.0e-6_dp)
      call t%check_close('... = E H/(E + H)', fd, youngs*hardening_modulus/(youngs + hardening_modulus), rtol=1.0e-6_dp)
      call extreme_hardening()
   end subroutine tangents

   !> E_t = E H/(E + H) wherever E_t is a double, against quadruple precision (whose range holds E H):
   !> H = 1e300 with steel's E gives E (E H overflowed to a NaN tangent); H = 0 gives 0; ordinary moduli
   !> give the bits of E H/(E + H) as written.
   subroutine extreme_hardening()
      real(dp), parameter :: pairs(2, 6) = reshape([2.0e11_dp, 1.0e300_dp, 2.0e11_dp, 0.0_dp, 1.0e200_dp, &
                                                    3.0e200_dp, huge(1.0_dp), huge(1.0_dp), 1.0e300_dp, 2.0e11_dp, &
                                                    youngs, hardening_modulus], [2, 6])
      real(real128) :: e, h
      integer :: k
      do k = 1, size(pairs, 2)
         e = real(pairs(1, k), real128)
         h = real(pairs(2, k), real128)
         call t%check_close('E_t of E = '//str(pairs(1, k))//', H = '//str(pairs(2, k))//' against quadruple precision', &
                            hardening_tangent(pairs(1, k), pairs(2, k)), real(e*h/(e + h), dp), rtol=4*epsilon(1.0_dp), &
                            atol=0.0_dp)
      end do
      call t%check('E_t of ordinary moduli: the bits of E H/(E + H)', hardening_tangent(youngs, hardening_modulus) == &
                   youngs*hardening_modulus/(youngs + hardening_modulus))
   end subroutine extreme_hardening

   real(dp) function fd_hencky(step, h)
      real(dp), intent(in) :: step, h
      real(dp) :: a, b, ja, jb
      a = 1.0e6_dp
      b = 1.0e6_dp
      ja = 0.97_dp
      jb = 0.97_dp
      call elastic_update(youngs, step + h, a, ja)
      call elastic_update(youngs, step - h, b, jb)
      fd_hencky = (a - b)/(2*h)
   end function fd_hencky
   real(dp) function linear_after(step, jac)
      real(dp), intent(in) :: step, jac
      real(dp) :: s, j
      s = youngs*(jac - 1.0_dp)
      j = jac
      call linear_update(youngs, step, s, j)
      linear_after = s
   end function linear_after
   real(dp) function plastic_after(step, stress, alpha)
      real(dp), intent(in) :: step, stress, alpha
      real(dp) :: s, e, a
      s = stress
      e = 0.0_dp
      a = alpha
      call radial_return(youngs, yield, hardening_modulus, step, s, e, a)
      plastic_after = s
   end function plastic_after

   subroutine names()
      call t%check('law names and ids agree', law_id('hencky') == law_hencky .and. law_id('linear') == law_linear &
                   .and. law_id('elastoplastic') == law_elastoplastic .and. law_id('plastic') == 0 .and. &
                   law_name(law_elastoplastic) == 'elastoplastic' .and. index(known_laws, 'linear') > 0)
   end subroutine names

   function real_text(x) result(text)
      real(dp), intent(in) :: x
      character(len=24) :: text
      write (text, '(es24.16)') x
   end function real_text
end program test_material_laws
