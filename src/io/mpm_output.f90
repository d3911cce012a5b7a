!> HDF5 output of one run (layout documented in README.md, "Output files").
module mpm_output
   use mpm_kinds, only: dp
   use mpm_errors, only: error_t
   use mpm_strings, only: str
   use mpm_config, only: config_t, config_namelist, config_parameters
   use mpm_registry, only: parameter_t, type_real, type_int, type_logical, type_text, type_real_list, format_value, &
                           parameter_listing
   use mpm_hdf5, only: h5_writer_t
   use mpm_version, only: code_version
   use mpm_diagnostics, only: status_name, status_ok, no_value
   use mpm_simulation, only: run_result_t, guard_message
   implicit none
   private
   public :: write_run_file, write_config_attributes

contains

   !> Write `result` of the run described by `config` to config%file (via a .part file).
   subroutine write_run_file(config, result, error)
      type(config_t), intent(in) :: config
      type(run_result_t), intent(in) :: result
      type(error_t), allocatable, intent(out) :: error
      type(h5_writer_t) :: h5
      integer :: i, n, k
      character(len=:), allocatable :: group
      logical :: stopped

      call h5%create(trim(config%file))
      call h5%attribute_string('/', 'code_version', code_version)
      call h5%attribute_string('/', 'content', 'single run')
      call h5%group('/config')
      call write_config_attributes(h5, '/config', config)

      if (config%history .and. result%history%recorded > 0) then
         n = result%history%recorded
         call h5%group('/history')
         call h5%write_real('/history/time', result%history%time(0:n - 1))
         call h5%write_real('/history/ucm', result%history%ucm(0:n - 1))
         call h5%write_real('/history/ucm_exact', result%history%ucm_exact(0:n - 1))
         call h5%write_real('/history/kinetic_energy', result%history%kinetic_energy(0:n - 1))
         call h5%write_real('/history/strain_energy', result%history%strain_energy(0:n - 1))
         if (allocated(result%history%plastic_work)) &
            call h5%write_real('/history/plastic_work', result%history%plastic_work(0:n - 1))
      end if

      ! a run a guard stopped has no result: its max_error and relative_error are no value (NaN), the
      ! error reached up to the stop has its own datasets (no value for a completed run)
      call h5%group('/summary')
      stopped = result%status /= status_ok
      call h5%write_real_scalar('/summary/max_error', merge(no_value, result%max_error, stopped))
      call h5%write_real_scalar('/summary/relative_error', merge(no_value, result%relative_error, stopped))
      call h5%write_real_scalar('/summary/error_before_stop', merge(result%max_error, no_value, stopped))
      call h5%write_real_scalar('/summary/relative_error_before_stop', merge(result%relative_error, no_value, stopped))
      call h5%write_real_scalar('/summary/ucm_amplitude', result%ucm_amplitude)
      call h5%write_int_scalar('/summary/steps', result%steps)
      call h5%write_int_scalar('/summary/steps_done', result%steps_done)
      call h5%write_int_scalar('/summary/particles', result%particles)
      call h5%write_real_scalar('/summary/dt', result%dt)
      call h5%write_real_scalar('/summary/run_time', result%run_time)
      call h5%write_int_scalar('/summary/status', result%status)
      call h5%write_string_scalar('/summary/status_name', status_name(result%status))
      if (result%status /= status_ok) then
         call h5%write_string_scalar('/summary/message', guard_message(result%status, result%trip, config))
      else
         call h5%write_string_scalar('/summary/message', 'completed')
      end if
      ! when a guard stopped the run, as numbers (0 when it completed)
      call h5%write_int_scalar('/summary/trip_step', merge(result%trip%step, 0, result%status /= status_ok))
      call h5%write_real_scalar('/summary/trip_time', merge(result%trip%time, 0.0_dp, result%status /= status_ok))
      call h5%write_real_scalar('/summary/initial_energy', result%initial_energy)
      call h5%write_real_scalar('/summary/final_energy', result%final_energy)
      call h5%write_real_scalar('/summary/max_energy_ratio', result%max_energy_ratio)
      call h5%write_real_scalar('/summary/min_volume_ratio', result%min_volume_ratio)
      call h5%write_real_scalar('/summary/max_cell_move', result%max_cell_move)
      call h5%write_real_scalar('/summary/min_node_mass_ratio', result%min_node_mass_ratio)
      call h5%write_string_scalar('/summary/error_measure', result%error_name//' ('//result%error_unit//')')
      if (allocated(result%report_names)) then
         do i = 1, size(result%report_names)
            call h5%write_real_scalar('/summary/'//trim(result%report_names(i)), result%report_values(i))
         end do
      end if

      if (allocated(result%snapshots)) then
         if (size(result%snapshots) > 0) call h5%group('/snapshots')
         do i = 1, size(result%snapshots)
            if (.not. allocated(result%snapshots(i)%x)) cycle ! not reached (run ended early)
            group = '/snapshots/'//pad(i)
            call h5%group(group)
            call h5%attribute_real(group, 'time', result%snapshots(i)%time)
            call h5%attribute_int(group, 'step', result%snapshots(i)%step)
            call h5%write_real(group//'/x', result%snapshots(i)%x)
            call h5%write_real(group//'/reference_x', result%snapshots(i)%x0)
            if (allocated(result%snapshots(i)%youngs_modulus)) &
               call h5%write_real(group//'/youngs_modulus', result%snapshots(i)%youngs_modulus)
            if (allocated(result%snapshots(i)%body)) call h5%write_int(group//'/body', result%snapshots(i)%body)
            if (allocated(result%snapshots(i)%plastic_strain)) &
               call h5%write_real(group//'/plastic_strain', result%snapshots(i)%plastic_strain)
            call h5%write_real(group//'/velocity', result%snapshots(i)%v)
            call h5%write_real(group//'/stress', result%snapshots(i)%stress)
            call h5%write_real(group//'/volume_ratio', result%snapshots(i)%volume_ratio)
            call h5%write_real(group//'/grid_x', result%snapshots(i)%grid_x)
            call h5%write_real(group//'/grid_velocity', result%snapshots(i)%grid_velocity)
            if (allocated(result%snapshots(i)%exact_names)) then
               do k = 1, size(result%snapshots(i)%exact_names)
                  call h5%write_real(group//'/exact_'//trim(result%snapshots(i)%exact_names(k)), &
                                     result%snapshots(i)%exact(:, k))
               end do
            end if
         end do
      end if
      call h5%finish(error)
   contains
      function pad(k) result(text)
         integer, intent(in) :: k
         character(len=4) :: text
         write (text, '(i4.4)') k
      end function pad
   end subroutine write_run_file

   !> The configuration as attributes of `group`: every variable of the parameter registry that the run's
   !> scene kind uses (under its attribute name; logicals as 0/1, an unset optional left out), the
   !> resolved quantities, the namelist text that reproduces the run and those registry entries
   !> themselves ('parameters', tab-separated).
   subroutine write_config_attributes(h5, group, config)
      type(h5_writer_t), intent(inout) :: h5
      character(len=*), intent(in) :: group
      type(config_t), intent(in) :: config
      type(config_t), target :: local
      type(parameter_t), allocatable :: table(:)
      integer :: i
      local = config
      call config_parameters(local, table)
      call h5%attribute_string(group, 'namelist', config_namelist(config))
      do i = 1, size(table)
         call write_one(table(i), trim(table(i)%attribute))
      end do
      call h5%attribute_real(group, 'wave_speed', config%wave_speed)
      call h5%attribute_real(group, 'dx', config%dx)
      call h5%attribute_real(group, 'dt', config%dt)
      call h5%attribute_real(group, 'period', config%period)
      call h5%attribute_real(group, 'final_time', config%final_time)
      call h5%attribute_int(group, 'steps', config%steps)
      call h5%attribute_string(group, 'parameters', parameter_listing(table))
   contains
      subroutine write_one(p, name)
         type(parameter_t), intent(in) :: p
         character(len=*), intent(in) :: name
         select case (p%type)
         case (type_real)
            if (len(format_value(p)) > 0) call h5%attribute_real(group, name, p%real_value)
         case (type_int)
            call h5%attribute_int(group, name, p%int_value)
         case (type_logical)
            call h5%attribute_int(group, name, merge(1, 0, p%logical_value))
         case (type_text)
            call h5%attribute_string(group, name, trim(p%text_value))
         case (type_real_list)
            call h5%attribute_reals(group, name, p%list_value(1:p%list_count))
         end select
      end subroutine write_one
   end subroutine write_config_attributes
end module mpm_output
