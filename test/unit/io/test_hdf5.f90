!> An HDF5 file written by the code reads back with the same values; no partial file is left.
program test_hdf5
   use mpm_kinds, only: dp, pi
   use mpm_strings, only: str
   use mpm_errors, only: error_t
   use mpm_config, only: config_t, resolve_config
   use mpm_simulation, only: run_result_t, run_simulation
   use mpm_output, only: write_run_file
   use mpm_hdf5, only: h5_read_real, h5_read_int, h5_read_attribute_real, h5_read_attribute_string, h5_read_string, &
                       h5_read_attribute_int, h5_writer_t
   use mpm_files, only: file_exists
   use mpm_version, only: code_version
   use mpm_testing, only: tester_t, tester, scratch_dir
   implicit none
   type(tester_t) :: t
   type(config_t) :: config
   type(run_result_t) :: r
   type(error_t), allocatable :: error
   real(dp), allocatable :: values(:)
   integer, allocatable :: ints(:)
   character(len=16), allocatable :: names(:)
   character(len=64) :: text
   real(dp) :: attribute
   character(len=:), allocatable :: dir, path

   t = tester('test_hdf5')
   dir = scratch_dir('hdf5')
   path = dir//'/run.h5'
   config%scheme = 'usf'
   config%elements = 7
   config%particles_per_element = 3
   config%dt_fraction = 0.25_dp
   config%file = path
   config%snapshot_count = 2
   config%snapshot_times(1:2) = [0.0_dp, 0.01_dp]
   call resolve_config(config)
   call run_simulation(config, r, error, record_history=.true.)  ! the run both cases write
   if (t%case('round_trip')) then
      call t%check('run set up', .not. allocated(error))
      call write_run_file(config, r, error)
      call t%check('file written', .not. allocated(error))
      call t%check('final file exists', file_exists(path))
      call t%check('no partial file left', .not. file_exists(path//'.part'))

      call h5_read_real(path, '/history/ucm', values, error)
      call t%check('history/ucm read', .not. allocated(error))
      call t%check('history/ucm identical', size(values) == r%history%recorded .and. &
                   all(values == r%history%ucm(0:r%history%recorded - 1)))
      call h5_read_real(path, '/history/strain_energy', values, error)
      call t%check('history/strain_energy identical', all(values == r%history%strain_energy(0:r%history%recorded - 1)))
      call h5_read_real(path, '/summary/max_error', values, error)
      call t%check('summary/max_error identical', values(1) == r%max_error)
      call h5_read_int(path, '/summary/steps', ints, error)
      call t%check('summary/steps identical', ints(1) == r%steps)
      call h5_read_real(path, '/snapshots/0002/stress', values, error)
      call t%check('snapshot stress identical', all(values == r%snapshots(2)%stress))
      call h5_read_real(path, '/snapshots/0001/grid_velocity', values, error)
      ! the grid domain: 7 elements of the bar, then the margin: the free end's amplitude v0/omega = 0.1/(pi/50 *
      ! sqrt(200e9/7800)) = 3.1e-4 m is under one cell (25/7 m), so 1 + 2 cells; 11 nodes
      call t%check('initial grid velocity has one value per node of the domain', size(values) == 11)
      call h5_read_real(path, '/snapshots/0001/grid_x', values, error)
      call t%check('grid domain ends 3 cells beyond the bar', abs(values(size(values)) - 10*25.0_dp/7) < 1.0e-12_dp)
      call h5_read_real(path, '/snapshots/0001/grid_velocity', values, error)
      call t%check('empty margin nodes have zero velocity', all(values(9:11) == 0.0_dp) .and. values(8) /= 0.0_dp)
      call h5_read_attribute_real(path, '/config', 'dt_fraction', attribute, error)
      call t%check('config attribute dt_fraction identical', attribute == 0.25_dp)
      call h5_read_attribute_string(path, '/', 'code_version', text, error)
      call t%check('code version attribute', trim(text) == code_version)
      call h5_read_string(path, '/summary/status_name', 16, names, error)
      call t%check('status name', trim(names(1)) == 'ok')
   end if

   if (t%case('periodic_snapshots')) call periodic_snapshots()

   ! A file that cannot be created leaves nothing behind and reports the path.
   if (t%case('unwritable_path')) then
      config%file = dir//'/no/such/folder/run.h5'
      call write_run_file(config, r, error)
      call t%check('unwritable path reported', allocated(error))
      if (allocated(error)) call t%check('message names the file', index(error%message, 'run.h5') > 0, error%message)
   end if
   if (t%case('string_columns')) call string_columns()
   call t%finish()

contains

   !> String datasets read back as written, trimmed: values of several lengths (an empty one, one
   !> filling its declared length, one with inner blanks), and an empty column.
   subroutine string_columns()
      character(len=12), parameter :: written(*) = [character(len=12) :: 'ok', '', 'twelve chars', 'a b  c', 'x']
      character(len=12) :: none(0)
      character(len=40), allocatable :: back(:)
      type(h5_writer_t) :: h5
      character(len=:), allocatable :: file
      integer :: i
      file = dir//'/strings.h5'
      call h5%create(file)
      call h5%write_strings('/texts', written)
      call h5%write_strings('/none', none)
      call h5%finish(error)
      call t%check('string file written', .not. allocated(error))
      if (allocated(error)) return
      call h5_read_string(file, '/texts', 40, back, error)
      call t%check('strings read back', .not. allocated(error))
      if (allocated(error)) return
      call t%check('one string per value', size(back) == size(written), str(size(back))//' strings')
      if (size(back) /= size(written)) return
      do i = 1, size(written)
         call t%check('string '//str(i)//" '"//trim(written(i))//"' read back", back(i) == written(i), &
                      "read '"//trim(back(i))//"'")
      end do
      call h5_read_string(file, '/none', 40, back, error)
      call t%check('an empty string column reads back empty', .not. allocated(error))
      if (.not. allocated(error)) call t%check('... with no string', size(back) == 0 .or. &
                                              (size(back) == 1 .and. len_trim(back(1)) == 0), str(size(back)))
   end subroutine string_columns

   !> snapshot_every = N: a snapshot at steps 0, N, 2N, ... besides those of snapshot_times, one per step
   !> where both fall on it; each with the scene's exact fields (the bar's velocity by hand).
   subroutine periodic_snapshots()
      type(config_t) :: periodic
      type(run_result_t) :: run
      integer, allocatable :: expected(:)
      integer :: k, every, timed, step
      real(dp), allocatable :: exact(:)
      real(dp) :: time, omega, beta
      character(len=4) :: name
      periodic = config
      periodic%file = dir//'/periodic.h5'
      periodic%snapshot_count = 2
      call resolve_config(periodic)
      every = periodic%steps/4 + 1               ! steps 0, every, 2 every, 3 every (the last below steps)
      timed = nint(0.01_dp/periodic%dt)          ! snapshot_times 0 and 0.01 s: steps 0 and `timed`
      periodic%snapshot_times(1:2) = [0.0_dp, timed*periodic%dt]
      periodic%snapshot_every = every
      expected = [0, every, 2*every, 3*every]
      if (all(expected /= timed)) expected = [pack(expected, expected < timed), timed, pack(expected, expected > timed)]
      call run_simulation(periodic, run, error, record_history=.false.)
      call write_run_file(periodic, run, error)
      call t%check('periodic snapshots: file written', .not. allocated(error))
      if (allocated(error)) return
      call t%check('periodic snapshots: '//str(size(expected))//' taken', &
                   count([(allocated(run%snapshots(k)%x), k=1, size(run%snapshots))]) == size(expected))
      omega = pi/(2*periodic%length)*periodic%wave_speed
      beta = pi/(2*periodic%length)
      do k = 1, size(expected)
         write (name, '(i4.4)') k
         call h5_read_attribute_int(periodic%file, '/snapshots/'//name, 'step', step, error)
         call t%check('periodic snapshot '//name//' at step '//str(expected(k)), step == expected(k), &
                      'step '//str(step))
         time = expected(k)*periodic%dt
         call h5_read_real(periodic%file, '/snapshots/'//name//'/reference_x', values, error)
         call h5_read_real(periodic%file, '/snapshots/'//name//'/exact_velocity', exact, error)
         call t%check('periodic snapshot '//name//': exact velocity read', .not. allocated(error))
         if (allocated(error)) return
         call t%check('periodic snapshot '//name//': exact velocity v0 cos(omega t) sin(beta X)', &
                      maxval(abs(exact - 0.1_dp*cos(omega*time)*sin(beta*values))) < 1.0e-15_dp)
      end do
      call h5_read_real(periodic%file, '/snapshots/'//'0006/x', values, error)
      call t%check('no snapshot beyond them', allocated(error))
   end subroutine periodic_snapshots
end program test_hdf5
