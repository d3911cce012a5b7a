!> The implicit integrators over every scene, shape and law (second tier: about a minute): each scene the
!> implicit integrator runs completes with every shape at the explicit step and at 4 times it, with an
!> error within 1.5 times explicit USL's at the same resolution (the same spatial discretisation: at a
!> step both resolve, the two agree); the quasi-static column completes for every shape and law within
!> 1 % of its closed form (linear shapes in one load step); and the consistent mass conserves the linear bar's energy over 100 periods
!> for every shape (to 1e-8; the lumped mass never gains).
program test_implicit_long
   use mpm_kinds, only: dp
   use mpm_strings, only: str
   use mpm_config, only: config_t, resolve_config, new_config
   use mpm_simulation, only: run_result_t, guard_message
   use mpm_diagnostics, only: status_ok, status_name
   use mpm_testing, only: tester_t, tester
   use mpm_testing_runs, only: run_resolved, set_values
   implicit none
   type(tester_t) :: t
   character(len=8), parameter :: shapes(5) = [character(len=8) :: 'linear', 'ugimp', 'cpgimp', 'bspline2', 'bspline3']
   character(len=16), parameter :: scenes(6) = [character(len=16) :: 'vibrating_bar', 'column', 'manufactured', &
                                                'composite_bar', 'impact', 'plastic_wave']
   integer :: s, k

   t = tester('test_implicit_long')
   if (t%case('scenes_against_explicit', long=.true.)) then
      do s = 1, size(scenes)
         do k = 1, size(shapes)
            call scene_against_explicit(trim(scenes(s)), trim(shapes(k)))
         end do
      end do
   end if
   if (t%case('static_column', long=.true.)) then
      do k = 1, size(shapes)
         call static_column(trim(shapes(k)))
      end do
   end if
   if (t%case('energy_over_100_periods', long=.true.)) then
      do k = 1, size(shapes)
         call energy_over_100_periods(trim(shapes(k)))
      end do
   end if
   call t%finish()

contains

   function scene_config(scene, shape) result(config)
      character(len=*), intent(in) :: scene, shape
      type(config_t) :: config
      config = new_config(scene)
      config%shape = shape
      config%elements = 40
      config%particles_per_element = 2
      config%periods = 1.0_dp
      select case (scene)
      case ('column')
         call set_values(config, ['scene.length=1.0'])
         call set_values(config, ['scene.youngs_modulus=1.0e8'])
         call set_values(config, ['scene.density=1000.0'])
      case ('manufactured')
         call set_values(config, ['scene.length=1.0'])
         call set_values(config, ['scene.youngs_modulus=1.0e7'])
         call set_values(config, ['scene.density=1000.0'])
         call set_values(config, ['scene.amplitude=1.0e-3'])
      case ('composite_bar')
         call set_values(config, ['scene.lengths=0.5, 0.5'])
         call set_values(config, ['scene.youngs_moduli=1.0e8, 1.6e9'])
         call set_values(config, ['scene.densities=1000.0, 1000.0'])
         call set_values(config, ['scene.drive_velocity=0.01'])
      case ('impact')
         call set_values(config, ['scene.lengths=0.5, 0.5'])
         call set_values(config, ['scene.youngs_moduli=1.0e8, 1.0e8'])
         call set_values(config, ['scene.densities=1000.0, 1000.0'])
         call set_values(config, ['scene.velocities=0.01, -0.01'])
         call set_values(config, ["scene.contact='none'"])
      case ('plastic_wave')
         call set_values(config, ['scene.length=1.0'])
         call set_values(config, ['scene.youngs_modulus=1.0e10'])
         call set_values(config, ['scene.density=1000.0'])
         call set_values(config, ['scene.drive_velocity=5.0'])
         config%law = 'elastoplastic'
         call set_values(config, ['material.yield_stress=1.0e7'])
         call set_values(config, ['material.hardening_modulus=1.0e9'])
         config%periods = 0.8_dp
      end select
   end function scene_config

   !> Implicit at the explicit step (dt = 0.2 dx/c) and at 4 times it against explicit USL at 0.2.
   subroutine scene_against_explicit(scene, shape)
      character(len=*), intent(in) :: scene, shape
      type(config_t) :: config
      type(run_result_t) :: explicit, implicit
      character(len=:), allocatable :: label
      real(dp) :: fraction
      integer :: i
      label = scene//' '//shape//': '
      config = scene_config(scene, shape)
      config%dt_fraction = 0.2_dp
      explicit = run_resolved(config)
      call t%check(label//'explicit completes', explicit%status == status_ok, status_name(explicit%status))
      do i = 1, 2
         fraction = merge(0.2_dp, 0.8_dp, i == 1)
         config = scene_config(scene, shape)
         config%integrator = 'implicit'
         config%dt_fraction = fraction
         call resolve_config(config)
         implicit = run_resolved(config)
         call t%check(label//'implicit at dt_fraction '//str(fraction)//' completes', implicit%status == status_ok, &
                      guard_message(implicit%status, implicit%trip, config))
         call t%check(label//'implicit at dt_fraction '//str(fraction)//': error '//str(implicit%relative_error)// &
                      ' within 1.5 times explicit''s '//str(explicit%relative_error), &
                      implicit%relative_error <= 1.5_dp*explicit%relative_error + 1.0e-12_dp)
      end do
   end subroutine scene_against_explicit

   !> The quasi-static column, every law: completes within 1 % of the closed form (20 % strain, 40
   !> elements x 2, 10 load steps).
   subroutine static_column(shape)
      character(len=*), intent(in) :: shape
      character(len=16), parameter :: laws(3) = [character(len=16) :: 'linear', 'hencky', 'elastoplastic']
      type(config_t) :: config
      type(run_result_t) :: r
      integer :: i
      do i = 1, size(laws)
         config = new_config()
         config%integrator = 'quasi_static'
         call set_values(config, ["scene.kind='column'"])
         config%law = laws(i)
         config%shape = shape
         config%elements = 40
         config%particles_per_element = 2
         call set_values(config, ['scene.length=1.0'])
         call set_values(config, ['scene.youngs_modulus=1.0e10'])
         call set_values(config, ['scene.density=1000.0'])
         call set_values(config, ['scene.gravity=2.0e6'])
         config%load_steps = 10
         ! (linear shapes: one load step, the equilibrium on the undeformed particles; after it, point
         ! particles carry sigma J per cell, an error of the order of the strain: docs/theory.md)
         if (shape == 'linear') config%load_steps = 1
         config%max_cell_move = 100.0_dp
         if (laws(i) == 'elastoplastic') then
            call set_values(config, ['material.yield_stress=1.0e9'])
            call set_values(config, ['material.hardening_modulus=2.0e9'])
         end if
         call resolve_config(config)
         r = run_resolved(config)
         call t%check('static column '//trim(laws(i))//' '//shape//': within 1 % ('//str(r%relative_error)//')', &
                      r%status == status_ok .and. r%relative_error < 0.01_dp, guard_message(r%status, r%trip, config))
      end do
   end subroutine static_column

   !> The trapezoidal rule with the consistent mass conserves the energy of the linear bar (small amplitude:
   !> no particle crosses a cell) over 100 periods at dt = 2 dx/c; the lumped mass never gains.
   subroutine energy_over_100_periods(shape)
      character(len=*), intent(in) :: shape
      type(config_t) :: config
      type(run_result_t) :: r
      real(dp) :: drift
      config%integrator = 'implicit'
      config%law = 'linear'
      config%shape = shape
      config%elements = 20
      config%particles_per_element = 2
      config%dt_fraction = 2.0_dp
      config%periods = 100.0_dp
      config%ghost_penalty = 0.0_dp
      config%mass = 'consistent'
      r = run_resolved(config)
      drift = maxval(abs(r%history%kinetic_energy + r%history%strain_energy - r%initial_energy))/r%initial_energy
      call t%check('consistent mass, '//shape//': energy over 100 periods within 1e-8 ('//str(drift)//')', &
                   r%status == status_ok .and. drift < 1.0e-8_dp)
      config%mass = 'lumped'
      r = run_resolved(config)
      call t%check('lumped mass, '//shape//': energy never grows over 100 periods', r%status == status_ok .and. &
                   r%max_energy_ratio <= 1.0_dp + 1.0e-12_dp, 'max energy ratio '//str(r%max_energy_ratio))
   end subroutine energy_over_100_periods

end program test_implicit_long
