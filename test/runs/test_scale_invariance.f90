!> Scale invariance: the same dimensionless problem at E from 1e-3 to 1e15 Pa and density from
!> 1e-20 to 1e20 kg/m^3 (v0 scaled with the wave speed, so v0/c is fixed) gives the same
!> dimensionless history (u_cm / amplitude against t / period, energy / initial energy) to near
!> round-off, the same number of steps, and no guard trips: no absolute threshold in the code.
program test_scale_invariance
   use mpm_kinds, only: dp
   use mpm_errors, only: error_t
   use mpm_config, only: config_t, resolve_config
   use mpm_simulation, only: run_result_t, run_simulation
   use mpm_diagnostics, only: status_ok
   use mpm_testing, only: tester_t, tester
   use mpm_testing_runs, only: set_value
   use mpm_strings, only: str
   implicit none
   type(tester_t) :: t
   type(run_result_t) :: reference, r
   real(dp), parameter :: moduli(3) = [1.0e-3_dp, 200.0e9_dp, 1.0e15_dp]
   real(dp), parameter :: densities(3) = [1.0e-20_dp, 7800.0_dp, 1.0e20_dp]
   real(dp), parameter :: lengths(2) = [1.0e-6_dp, 25.0e3_dp]
   real(dp) :: v0_over_c, worst_ucm, worst_energy
   integer :: i, j, k
   character(len=4), parameter :: schemes(3) = ['usf ', 'usl ', 'musl']

   t = tester('test_scale_invariance')
   v0_over_c = 0.1_dp/sqrt(200.0e9_dp/7800.0_dp)
   do k = 1, size(schemes)
      if (.not. t%case(trim(schemes(k)))) cycle
      reference = run(trim(schemes(k)), 200.0e9_dp, 7800.0_dp, 25.0_dp)
      worst_ucm = 0.0_dp
      worst_energy = 0.0_dp
      do i = 1, size(moduli)
         do j = 1, size(densities)
            r = run(trim(schemes(k)), moduli(i), densities(j), 25.0_dp)
            call compare(r)
         end do
      end do
      do i = 1, size(lengths)
         r = run(trim(schemes(k)), 200.0e9_dp, 7800.0_dp, lengths(i))
         call compare(r)
      end do
      print '(a,2es10.2)', 'test_scale_invariance: '//trim(schemes(k))//' worst dimensionless differences (u_cm, energy):', &
         worst_ucm, worst_energy
   end do
   call t%finish()

contains

   subroutine compare(res)
      type(run_result_t), intent(in) :: res
      real(dp) :: d_ucm, d_energy
      integer :: n
      n = reference%history%recorded
      call t%check('completes without a guard', res%status == status_ok)
      call t%check('same number of steps', res%steps == reference%steps .and. res%history%recorded == n)
      if (res%history%recorded /= n) return
      d_ucm = maxval(abs(res%history%ucm(0:n - 1)/res%ucm_amplitude - &
                         reference%history%ucm(0:n - 1)/reference%ucm_amplitude))
      d_energy = maxval(abs(energy(res) - energy(reference)))
      call t%check_close('same dimensionless u_cm history', d_ucm, 0.0_dp, atol=1.0e-9_dp)
      call t%check_close('same dimensionless energy history', d_energy, 0.0_dp, atol=1.0e-9_dp)
      call t%check_close('same relative error', res%relative_error, reference%relative_error, rtol=1.0e-7_dp)
      worst_ucm = max(worst_ucm, d_ucm)
      worst_energy = max(worst_energy, d_energy)
   end subroutine compare

   function energy(res) result(e)
      type(run_result_t), intent(in) :: res
      real(dp), allocatable :: e(:)
      integer :: n
      n = res%history%recorded
      e = (res%history%kinetic_energy(0:n - 1) + res%history%strain_energy(0:n - 1))/res%initial_energy
   end function energy

   function run(scheme, youngs, density, length) result(res)
      character(len=*), intent(in) :: scheme
      real(dp), intent(in) :: youngs, density, length
      type(run_result_t) :: res
      type(config_t) :: config
      type(error_t), allocatable :: error
      config%scheme = scheme
      call set_value(config, 'scene.youngs_modulus='//str(youngs))
      call set_value(config, 'scene.density='//str(density))
      call set_value(config, 'scene.length='//str(length))
      call set_value(config, 'scene.velocity_amplitude='//str(v0_over_c*sqrt(youngs/density)))
      config%elements = 10
      config%particles_per_element = 3
      config%dt_fraction = 0.3_dp
      config%periods = 3.0_dp
      call resolve_config(config)
      call run_simulation(config, res, error, record_history=.true.)
      if (allocated(error)) error stop 'run failed to start'
   end function run
end program test_scale_invariance
