!> HDF5 output of one run (layout documented in README.md, "Output files").
module mpm_output
   use mpm_kinds, only: dp
   use mpm_errors, only: error_t
   use mpm_strings, only: str
   use mpm_config, only: config_t, config_namelist, unset
   use mpm_hdf5, only: h5_writer_t
   use mpm_version, only: code_version
   use mpm_diagnostics, only: status_name, status_ok
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
      integer :: i, n
      character(len=:), allocatable :: group

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
      end if

      call h5%group('/summary')
      call h5%write_real_scalar('/summary/max_error', result%max_error)
      call h5%write_real_scalar('/summary/relative_error', result%relative_error)
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
      call h5%write_real_scalar('/summary/initial_energy', result%initial_energy)
      call h5%write_real_scalar('/summary/final_energy', result%final_energy)
      call h5%write_real_scalar('/summary/max_energy_ratio', result%max_energy_ratio)
      call h5%write_real_scalar('/summary/min_volume_ratio', result%min_volume_ratio)
      call h5%write_real_scalar('/summary/max_cell_move', result%max_cell_move)
      call h5%write_real_scalar('/summary/min_node_mass_ratio', result%min_node_mass_ratio)

      if (allocated(result%snapshots)) then
         if (size(result%snapshots) > 0) call h5%group('/snapshots')
         do i = 1, size(result%snapshots)
            if (.not. allocated(result%snapshots(i)%x)) cycle ! not reached (run ended early)
            group = '/snapshots/'//pad(i)
            call h5%group(group)
            call h5%attribute_real(group, 'time', result%snapshots(i)%time)
            call h5%attribute_int(group, 'step', result%snapshots(i)%step)
            call h5%write_real(group//'/x', result%snapshots(i)%x)
            call h5%write_real(group//'/velocity', result%snapshots(i)%v)
            call h5%write_real(group//'/stress', result%snapshots(i)%stress)
            call h5%write_real(group//'/volume_ratio', result%snapshots(i)%volume_ratio)
            call h5%write_real(group//'/grid_x', result%snapshots(i)%grid_x)
            call h5%write_real(group//'/grid_velocity', result%snapshots(i)%grid_velocity)
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

   !> The configuration as attributes of `group`: every namelist value, the resolved quantities
   !> and the namelist text that reproduces the run.
   subroutine write_config_attributes(h5, group, config)
      type(h5_writer_t), intent(inout) :: h5
      character(len=*), intent(in) :: group
      type(config_t), intent(in) :: config
      call h5%attribute_string(group, 'namelist', config_namelist(config))
      call h5%attribute_string(group, 'scene_kind', trim(config%scene_kind))
      call h5%attribute_real(group, 'length', config%length)
      call h5%attribute_real(group, 'youngs_modulus', config%youngs_modulus)
      call h5%attribute_real(group, 'density', config%density)
      call h5%attribute_real(group, 'velocity_amplitude', config%velocity_amplitude)
      call h5%attribute_int(group, 'mode', config%mode)
      call h5%attribute_string(group, 'scheme', trim(config%scheme))
      call h5%attribute_int(group, 'elements', config%elements)
      call h5%attribute_int(group, 'particles_per_element', config%particles_per_element)
      call h5%attribute_real(group, 'dt_fraction', config%dt_fraction)
      call h5%attribute_int(group, 'margin_cells', config%margin_cells)
      call h5%attribute_string(group, 'kernels', trim(config%kernels))
      if (config%end_time /= unset) then
         call h5%attribute_real(group, 'end_time', config%end_time)
      else
         call h5%attribute_real(group, 'periods', config%periods)
      end if
      call h5%attribute_real(group, 'energy_growth_limit', config%energy_growth_limit)
      call h5%attribute_real(group, 'max_cell_move', config%max_cell_move)
      call h5%attribute_real(group, 'wave_speed', config%wave_speed)
      call h5%attribute_real(group, 'dx', config%dx)
      call h5%attribute_real(group, 'dt', config%dt)
      call h5%attribute_real(group, 'period', config%period)
      call h5%attribute_real(group, 'final_time', config%final_time)
      call h5%attribute_int(group, 'steps', config%steps)
      call h5%attribute_string(group, 'output_file', trim(config%file))
   end subroutine write_config_attributes
end module mpm_output
