!> XPIC(m) and FMPM(k) on the fused kernels (mpm_fused; the projection in mpm_fused_projection) against the
!> generic path, which is their definition (cross-checked against the NumPy reference), run by run with
!> `kernels='generic'` as the only difference (mpm_testing_runs' check_fused_config: the path asked for,
!> same status and steps, u_cm histories equal to round-off, the last kinetic energies to 1e-10):
!> - xpic: the bar with particles crossing cells, USF, USL and MUSL, m = 1, 2, 3 and 5; the column (a grid
!>   load) with USL, m = 2;
!> - fmpm: the same bar with USF and USL, k = 1, 2, 3 and 5; the column with USF, k = 2; MUSL stays on the
!>   generic path (its remapped velocity would need the start-of-step positions after the particles moved);
!> - cpdi: CPDI's lean USL step (mpm_fused_cpdi) on the same bar with FLIP, PIC and the blend, the linear
!>   and the elastoplastic law (yielding), and at v0 = 0.3 c (J from about 0.7 to 1.3: domains far from their
!>   first cells); a domain stretched beyond four nodes stops it where it stops the generic path; USF and
!>   the manufactured solution's forces stay on the generic path;
!> - threads: a run cut into segments (1e5 particles), XPIC(2), FMPM(2) and CPDI with USL: the fast run on 2
!>   threads gives the 1-thread histories bit for bit, and both agree with the generic path.
!> Small runs but the last (1e5 particles, 20 steps): seconds.
program test_cures_fused
   use mpm_kinds, only: dp
   use mpm_config, only: config_t, new_config
   use mpm_simulation, only: run_result_t
   use mpm_strings, only: str
   use mpm_diagnostics, only: status_domain_stretched, status_name
   use mpm_testing, only: tester_t, tester
   use mpm_testing_runs, only: check_fused_config, run_resolved, moving_bar, set_bar_speed, set_value
   implicit none
   type(tester_t) :: t
   character(len=4), parameter :: schemes(3) = ['usf ', 'usl ', 'musl']
   integer, parameter :: orders(4) = [1, 2, 3, 5]
   integer :: i, j
   type(config_t) :: config

   t = tester('test_cures_fused')
   if (t%case('xpic')) then
      do i = 1, size(schemes)
         do j = 1, size(orders)
            call check_fused_config(t, 'bar '//trim(schemes(i))//' XPIC('//str(orders(j))//'): ', &
                                    crossing_bar(trim(schemes(i)), 'xpic', orders(j)))
         end do
      end do
      call check_fused_config(t, 'column usl XPIC(2): ', column('usl', 'xpic', 2))
   end if
   if (t%case('fmpm')) then
      do i = 1, 2
         do j = 1, size(orders)
            call check_fused_config(t, 'bar '//trim(schemes(i))//' FMPM('//str(orders(j))//'): ', &
                                    crossing_bar(trim(schemes(i)), 'fmpm', orders(j)))
         end do
      end do
      call check_fused_config(t, 'column usf FMPM(2): ', column('usf', 'fmpm', 2))
      call generic_only()
   end if
   if (t%case('cpdi')) call cpdi()
   if (t%case('threads')) then
      call check_fused_config(t, 'large bar usl XPIC(2): ', large_bar('xpic'), segments=.true.)
      call check_fused_config(t, 'large bar usl FMPM(2): ', large_bar('fmpm'), segments=.true.)
      config = large_bar('flip')
      config%shape = 'cpdi'
      call check_fused_config(t, 'large bar usl CPDI: ', config, segments=.true.)
   end if
   call t%finish()

contains

   !> The bar, 30 elements x 3 particles, dt = 0.3 dx/c, v0 = 0.01 c (particles cross cells), one period,
   !> with `transfer` of order `order`.
   function crossing_bar(scheme, transfer, order) result(config)
      character(len=*), intent(in) :: scheme, transfer
      integer, intent(in) :: order
      type(config_t) :: config
      config = moving_bar(scheme, 30, 3, 0.3_dp, 1.0_dp, 0.01_dp)
      config%transfer = transfer
      config%xpic_order = 1
      config%fmpm_order = 1
      if (transfer == 'xpic') config%xpic_order = order
      if (transfer == 'fmpm') config%fmpm_order = order
   end function crossing_bar

   !> The column under its weight (a grid load), 40 elements x 2 particles, with `transfer` of order `order`.
   function column(scheme, transfer, order) result(config)
      character(len=*), intent(in) :: scheme, transfer
      integer, intent(in) :: order
      type(config_t) :: config
      config = new_config('column')
      config%scheme = scheme
      config%transfer = transfer
      if (transfer == 'xpic') config%xpic_order = order
      if (transfer == 'fmpm') config%fmpm_order = order
      config%elements = 40
      config%particles_per_element = 2
      config%dt_fraction = 0.2_dp
   end function column

   !> The bar of 50,000 elements x 2 particles (cut into segments), USL, 20 steps, `transfer` of order 2.
   function large_bar(transfer) result(config)
      character(len=*), intent(in) :: transfer
      type(config_t) :: config
      config = crossing_bar('usl', transfer, 2)
      config%elements = 50000
      config%particles_per_element = 2
      config%periods = 20*0.3_dp/(4.0_dp*50000)
   end function large_bar

   !> CPDI's lean step against the generic path, and the runs it leaves to the generic path.
   subroutine cpdi()
      character(len=5), parameter :: transfers(3) = ['flip ', 'pic  ', 'blend']
      type(config_t) :: config
      type(run_result_t) :: res, generic
      integer :: k
      do k = 1, size(transfers)
         config = crossing_bar('usl', trim(transfers(k)), 1)
         config%shape = 'cpdi'
         config%flip_fraction = 0.75_dp
         call check_fused_config(t, 'bar usl CPDI '//trim(transfers(k))//': ', config)
      end do
      config = crossing_bar('usl', 'flip', 1)
      config%shape = 'cpdi'
      config%law = 'linear'
      call check_fused_config(t, 'bar usl CPDI, law linear: ', config)
      config%law = 'elastoplastic'
      call set_value(config, 'material.yield_stress=1.0e7')
      call check_fused_config(t, 'bar usl CPDI, law elastoplastic: ', config)
      config = crossing_bar('usl', 'flip', 1)
      config%shape = 'cpdi'
      call set_bar_speed(config, 0.3_dp)
      config%periods = 0.5_dp
      call check_fused_config(t, 'bar usl CPDI, v0 = 0.3 c: ', config)
      ! a domain stretched beyond the four nodes: the lean step stops where the generic path stops
      config = crossing_bar('usl', 'flip', 1)
      config%shape = 'cpdi'
      config%particles_per_element = 1
      call set_bar_speed(config, 2.0_dp)
      config%energy_growth_limit = 1.0e10_dp
      res = run_resolved(config)
      config%kernels = 'generic'
      generic = run_resolved(config)
      call t%check('bar usl CPDI stretched: the lean step stops with domain_stretched at the generic path''s step', &
                   res%fused .and. res%status == status_domain_stretched .and. generic%status == res%status .and. &
                   res%steps_done == generic%steps_done, status_name(res%status)//' after '//str(res%steps_done)// &
                   ' steps, generic '//status_name(generic%status)//' after '//str(generic%steps_done))
      config = crossing_bar('usf', 'flip', 1)
      config%shape = 'cpdi'
      res = run_resolved(config)
      call t%check('bar usf CPDI: auto keeps the generic path', .not. res%fused)
      config = new_config('manufactured')
      config%shape = 'cpdi'
      config%elements = 20
      res = run_resolved(config)
      call t%check('manufactured usl CPDI: auto keeps the generic path', .not. res%fused)
   end subroutine cpdi

   !> FMPM with MUSL runs on the generic path (auto does not choose the fused kernels).
   subroutine generic_only()
      type(run_result_t) :: res
      res = run_resolved(crossing_bar('musl', 'fmpm', 2))
      call t%check('bar musl FMPM(2): auto keeps the generic path', .not. res%fused)
   end subroutine generic_only
end program test_cures_fused
