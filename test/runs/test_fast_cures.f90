!> The cures on the fused kernels (docs/performance.md, The cures on the fused kernels) against the generic
!> path, which is their definition (cross-checked with the NumPy reference: test/reference), run by run with
!> `kernels='generic'` as the only difference (mpm_testing_runs' check_paths_agree: the paths asked for, same
!> status and steps, u_cm histories equal to round-off, the last kinetic energies to 1e-10):
!> - asflip_fast: ASFLIP on the hat's kernels (variant asflip), USF, USL and MUSL, alpha 0.99, 0.5 and 0, the
!>   bar at v0 = 0.02 c (particles cross cells, and both branches of the separation test are taken: some
!>   particles are compressed beyond ln J = -1e-3), the hencky and the linear law; and a run of 1e5
!>   particles cut into segments, whose 2-thread histories equal its 1-thread ones bit for bit; the bar at
!>   v0 = 0.2 c on 8 elements, dt = 0.8 dx/c, whose strain increments of several percent a step take the
!>   separation test's library exp (mpm_transfer's asflip_separation).
!> - total_fast: the total-Lagrangian formulation on the hat's kernels (variant total), FLIP, USF, USL and
!>   MUSL, the same bar (particles cross cells of the current configuration, never of the reference one)
!>   with the hencky, the linear and the elastoplastic law (yielding), and the column (a grid load); the
!>   same run of 1e5 particles on 1 and 2 threads.
!> Small runs: seconds.
program test_fast_cures
   use mpm_kinds, only: dp
   use mpm_config, only: config_t, new_config
   use mpm_strings, only: str
   use mpm_testing, only: tester_t, tester
   use mpm_testing_runs, only: check_fused_config, set_value, set_values, moving_bar, set_bar_speed
   implicit none
   character(len=4), parameter :: schemes(3) = ['usf ', 'usl ', 'musl']
   real(dp), parameter :: alphas(3) = [0.99_dp, 0.5_dp, 0.0_dp]
   character(len=4), parameter :: alpha_names(3) = ['0.99', '0.5 ', '0   ']
   type(tester_t) :: t
   type(config_t) :: config
   integer :: i, j

   t = tester('test_fast_cures')
   if (t%case('asflip_fast')) then
      do i = 1, size(schemes)
         do j = 1, size(alphas)
            config = crossing_bar(trim(schemes(i)))
            config%transfer = 'asflip'
            config%asflip_alpha = alphas(j)
            call check_fused_config(t, 'ASFLIP('//trim(alpha_names(j))//') '//trim(schemes(i))//': ', config)
            config%law = 'linear'
            call check_fused_config(t, 'ASFLIP('//trim(alpha_names(j))//') '//trim(schemes(i))//', law linear: ', config)
         end do
      end do
      ! strain increments of several percent a step (beyond the separation test's polynomial exp)
      do i = 1, size(schemes)
         config = crossing_bar(trim(schemes(i)))
         config%transfer = 'asflip'
         config%asflip_alpha = 0.99_dp
         config%elements = 8
         config%dt_fraction = 0.8_dp
         call set_bar_speed(config, 0.2_dp)
         config%energy_growth_limit = 1.0e10_dp
         call check_fused_config(t, 'ASFLIP(0.99) '//trim(schemes(i))//', v0 = 0.2 c: ', config)
      end do
      config = segmented_bar('usl')
      config%transfer = 'asflip'
      config%asflip_alpha = 0.99_dp
      call check_fused_config(t, 'ASFLIP(0.99) usl, 1e5 particles: ', config, segments=.true.)
   end if
   if (t%case('total_fast')) then
      do i = 1, size(schemes)
         config = crossing_bar(trim(schemes(i)))
         config%formulation = 'total'
         call check_fused_config(t, 'total '//trim(schemes(i))//': ', config)
         config%law = 'linear'
         call check_fused_config(t, 'total '//trim(schemes(i))//', law linear: ', config)
         config%law = 'elastoplastic'
         ! (a third of the largest elastic stress E v0/c, hardening E/10)
         call set_value(config, 'material.yield_stress='//str(0.3_dp*0.02_dp*200.0e9_dp))
         call set_value(config, 'material.hardening_modulus=20.0e9')
         call check_fused_config(t, 'total '//trim(schemes(i))//', law elastoplastic: ', config)
         config = new_config()
         call set_values(config, ["scene.kind='column'"])
         config%scheme = trim(schemes(i))
         config%formulation = 'total'
         config%elements = 30
         config%particles_per_element = 3
         call check_fused_config(t, 'total '//trim(schemes(i))//', column: ', config)
      end do
      config = segmented_bar('usl')
      config%formulation = 'total'
      call check_fused_config(t, 'total usl, 1e5 particles: ', config, segments=.true.)
   end if
   call t%finish()

contains

   !> The bar at v0 = 0.02 c (strains up to 2 %, particles crossing cells), 30 elements x 3 particles,
   !> dt = 0.3 dx/c, one period.
   function crossing_bar(scheme) result(config)
      character(len=*), intent(in) :: scheme
      type(config_t) :: config
      config = moving_bar(scheme, 30, 3, 0.3_dp, 1.0_dp, 0.02_dp)
   end function crossing_bar

   !> The same bar on 50,000 elements x 2 particles (cut into segments, run on threads), 200 steps.
   function segmented_bar(scheme) result(config)
      character(len=*), intent(in) :: scheme
      type(config_t) :: config
      config = moving_bar(scheme, 50000, 2, 0.5_dp, 0.0005_dp, 0.02_dp)
   end function segmented_bar
end program test_fast_cures
