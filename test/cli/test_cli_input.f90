!> The mpm1d executable: bad input never reaches the time loop (non-zero exit, a message naming the
!> variable, no output file), the default run, --help, and a guard trip that keeps the history.
program test_cli_input
   use mpm_kinds, only: dp
   use mpm_errors, only: error_t
   use mpm_hdf5, only: h5_read_real, h5_read_int
   use mpm_files, only: file_exists, absolute_path
   use mpm_testing, only: tester_t, tester, run_app, scratch_dir, app_path
   implicit none
   type(tester_t) :: t
   character(len=:), allocatable :: dir
   integer :: cases

   t = tester('test_cli_input')
   dir = scratch_dir('cli')
   cases = 0

   ! ---- malformed input: each case names what must appear in the message ----
   if (t%case('malformed_inputs')) then
      call bad('misspelled variable', "&scene lenght=25.0 /", 'lenght')
      call bad('misspelled group', "&discretization elements=3 /", 'discretization')
      call bad('real for an integer', "&discretisation elements=2.5 /", "'elements'")
      call bad('unquoted string', "&discretisation scheme=usl /", "'scheme'")
      call bad('text for a real', "&scene length=abc /", "'length'")
      call bad('two values for a scalar', "&discretisation elements=2 3 /", "'elements'")
      call bad('integer overflow', "&discretisation elements=99999999999 /", 'elements')
      call bad('NaN', "&scene youngs_modulus=NaN /", 'youngs_modulus')
      call bad('Infinity', "&scene density=Infinity /", 'density')
      call bad('negative length', "&scene length=-25.0 /", 'length')
      call bad('zero density', "&scene density=0.0 /", 'density')
      call bad('zero elements', "&discretisation elements=0 /", 'elements')
      call bad('negative particles', "&discretisation particles_per_element=-2 /", 'particles_per_element')
      call bad('zero time step', "&discretisation dt_fraction=0.0 /", 'dt_fraction')
      call bad('negative time step', "&discretisation dt_fraction=-0.1 /", 'dt_fraction')
      call bad('absurd time step', "&discretisation dt_fraction=100.0 /", 'dt_fraction')
      call bad('NaN time step', "&discretisation dt_fraction=NaN /", 'dt_fraction')
      call bad('mode zero', "&scene mode=0 /", 'mode')
      call bad('NaN amplitude', "&scene velocity_amplitude=NaN /", 'velocity_amplitude')
      call bad('unknown scheme', "&discretisation scheme='usx' /", 'scheme')
      call bad('unknown scene', "&scene kind='beam' /", 'kind')
      call bad('end time shorter than a step', "&run end_time=1.0e-9 /", 'end time')
      call bad('negative periods', "&run periods=-2.0 /", 'periods')
      call bad('periods and end_time', "&run periods=2.0, end_time=0.04 /", 'periods or end_time')
      call bad('missing slash', "&scene length=25.0", "not terminated by '/'")
      call bad('group given twice', "&scene length=3 / &scene length=4 /", 'given twice')
      call bad('output folder missing', "&output file='no_such_folder/bar.h5' /", 'does not exist')
      call bad('output folder missing: where it was given and the absolute path tried', &
               "&scene length=25.0 /"//new_line('a')//"&output file='no_such_folder/bar.h5' /", &
               "bad.nml:2: output: file = 'no_such_folder/bar.h5': folder 'no_such_folder' does not exist (looked for "// &
               absolute_path(dir)//"/no_such_folder, relative to the folder mpm1d runs in)")
      call bad('snapshot_every: more snapshots than allowed (1600 steps)', "&output snapshot_every=1 /", &
               "output: snapshot_every = 1 takes 1601 snapshots over the run's 1600 steps; allowed: at most 1000 "// &
               "snapshots, snapshot_every >= 2")
      call bad('snapshot_every negative', "&output snapshot_every=-3 /", 'snapshot_every')
      call bad('empty output name', "&output file='' /", 'file')
      call bad('snapshot after the end', "&output snapshot_times=10.0 /", 'snapshot_times')
      call bad('too many particles', "&discretisation elements=2000000000, particles_per_element=2 /", &
               'elements*particles_per_element')
      call bad('more memory than the machine has', &
               "&discretisation elements=1000000000, particles_per_element=2 / &run end_time=1.0e-11 /", &
               'memory available')
      call bad('no finite wave speed', "&scene youngs_modulus=1.0e300, density=1.0e-300 /", 'wave speed')
      call bad('every problem reported', "&scene length=-1.0, density=-2.0 /&discretisation elements=0 /", 'elements')
      call bad('bad energy guard', "&guards energy_growth_limit=0.5 /", 'energy_growth_limit')
      call bad('unknown guard', "&guards energy_limit=3.0 /", 'energy_limit')
      call bad('empty list in a sweep', "&sweep elements= /", 'empty list')
      call bad('bad list value in a sweep', "&sweep particles_per_element=1, -4 /", 'particles_per_element(2)')
      call bad('bad shard in a sweep', "&sweep shard=0 /", 'shard')
      ! issue 24: a NUL byte in the output name (it wrote a file 'out'), a drive the grid's margin cannot
      ! hold (it crashed), flip_fraction without transfer = 'blend' (silently unused), an impact gap
      ! refused through periods, a misspelled group without a suggestion
      call bad('NUL byte in the output file name', "&output file='out"//achar(0)//".h5' /", "'out\0.h5' holds a NUL byte")
      call t%check('NUL byte in the output file name: no file out', .not. file_exists(dir//'/out'))
      call bad('composite drive_velocity 1e10', "&scene kind='composite_bar', lengths=1.0, 1.0, youngs_moduli=16e6, "// &
               "1e6, densities=1000, 1000, drive_velocity=1e10 /", 'allowed: at most 1e8 cells, drive_velocity <=')
      call bad('flip_fraction with FLIP', "&discretisation flip_fraction=0.5 /", "not with transfer = 'flip'")
      call bad('impact gap 1e300', "&scene kind='impact', lengths=1.0, 1.0, youngs_moduli=1e9, 1e9, densities=1000, "// &
               "1000, velocities=1, -1, gap=1e300 /", 'scene: gap = 1e300 m')
      call bad('misspelled group suggested', "&discretization elements=3 /", 'did you mean &discretisation?')
      call bad_file('missing input file', 'no_such_input.nml', 'cannot open')
      call bad_file('input is a folder', '.', 'input')
      print '(a,i0,a)', 'test_cli_input: ', cases, ' malformed inputs checked'
   end if

   if (t%case('default_run')) call default_run()
   if (t%case('help_and_usage')) call help_and_usage()
   if (t%case('guard_trip')) call guard_trip()
   if (t%case('killed_run')) call killed_run()
   call t%finish()

contains

   !> Write `text` as the input file, run, expect exit 2, `part` in the message and no output.
   subroutine bad(label, text, part)
      character(len=*), intent(in) :: label, text, part
      integer :: unit
      open (newunit=unit, file=dir//'/bad.nml', status='replace', action='write')
      write (unit, '(a)') text
      close (unit)
      call bad_file(label, 'bad.nml', part)
   end subroutine bad

   subroutine bad_file(label, input, part)
      character(len=*), intent(in) :: label, input, part
      integer :: status
      character(len=:), allocatable :: output
      cases = cases + 1
      call execute_command_line('rm -f '//dir//'/*.h5 '//dir//'/*.part')
      call run_app(dir, input, status, output)
      call t%check(label//': exit code 2', status == 2, 'exit code '//itoa(status)//'; output: '//output)
      call t%check_contains(label//': message', output, part)
      call t%check_contains(label//': message prefix', output, 'mpm1d: ')
      call t%check(label//': no output file', .not. file_exists(dir//'/bar.h5') .and. &
                   .not. file_exists(dir//'/bar.h5.part'))
      call t%check(label//': stopped before the time loop', index(output, 'run time') == 0)
   end subroutine bad_file

   !> No argument: the paper's verification case, written to bar.h5, error as in Fig. 3b.
   subroutine default_run()
      integer :: status
      character(len=:), allocatable :: output
      real(dp), allocatable :: values(:)
      type(error_t), allocatable :: error
      call run_app(dir, '', status, output)
      call t%check('default run exit 0', status == 0, output)
      call t%check_contains('default run says where it wrote (the absolute path)', output, 'wrote '//absolute_path(dir//'/bar.h5'))
      call h5_read_real(dir//'/bar.h5', '/summary/relative_error', values, error)
      call t%check('default run summary readable', .not. allocated(error))
      if (.not. allocated(error)) call t%check('default run error under 1.5 % of the amplitude', &
                                               values(1) < 0.015_dp .and. values(1) > 0.0_dp)
   end subroutine default_run

   subroutine help_and_usage()
      integer :: status
      character(len=:), allocatable :: output
      call run_app(dir, '--help', status, output)
      call t%check('--help exit 0', status == 0)
      call t%check_contains('--help lists the namelist', output, '&discretisation')
      call run_app(dir, '--frobnicate', status, output)
      call t%check('unknown option exit 2', status == 2)
      call run_app(dir, 'a.nml b.nml', status, output)
      call t%check('two inputs exit 2', status == 2)
   end subroutine help_and_usage

   !> An unstable run (USL at 3 times the critical step) is stopped by a guard: exit 1, a message
   !> with step and particle, and the history so far with the status in the file.
   subroutine guard_trip()
      integer :: status, unit
      character(len=:), allocatable :: output
      real(dp), allocatable :: ucm(:)
      integer, allocatable :: code(:), steps(:)
      type(error_t), allocatable :: error
      open (newunit=unit, file=dir//'/unstable.nml', status='replace', action='write')
      write (unit, '(a)') "&discretisation scheme='usl', dt_fraction=3.0 /", "&output file='unstable.h5' /"
      close (unit)
      call run_app(dir, 'unstable.nml', status, output)
      call t%check('unstable run exit 1', status == 1, output)
      call t%check_contains('warning about the stability limit', output, 'above the linear stability limit')
      call t%check_contains('guard message names the guard', output, 'guard ')
      call t%check_contains('guard message gives the particle', output, 'particle ')
      call h5_read_int(dir//'/unstable.h5', '/summary/status', code, error)
      call t%check('unstable run file has a non-zero status', .not. allocated(error))
      if (allocated(error)) return
      call t%check('status recorded', code(1) /= 0)
      call h5_read_int(dir//'/unstable.h5', '/summary/steps_done', steps, error)
      call h5_read_real(dir//'/unstable.h5', '/history/ucm', ucm, error)
      call t%check('history kept up to the trip', size(ucm) == steps(1) + 2)
   end subroutine guard_trip

   !> A run killed midway leaves nothing under its final name.
   subroutine killed_run()
      integer :: status, unit
      open (newunit=unit, file=dir//'/long.nml', status='replace', action='write')
      write (unit, '(a)') "&discretisation elements=2000, particles_per_element=10, dt_fraction=0.05 /", &
         "&run periods=200.0 /", "&output file='long.h5', history=.false. /"
      close (unit)
      call execute_command_line('cd '//dir//' && timeout -s KILL 1 '//app_path()//' long.nml > /dev/null 2>&1', &
                                exitstat=status)
      call t%check('long run was killed', status /= 0)
      call t%check('killed run leaves no file under the final name', .not. file_exists(dir//'/long.h5'))
      ! a crash between the complete partial file and its rename (the test hook aborts there)
      open (newunit=unit, file=dir//'/crash.nml', status='replace', action='write')
      write (unit, '(a)') "&output file='crash.h5' /"
      close (unit)
      call execute_command_line('cd '//dir//' && rm -f crash.h5 crash.h5.*.part && MPM1D_CRASH_BEFORE_RENAME=1 '// &
                                app_path()//' crash.nml > /dev/null 2>&1', exitstat=status)
      call t%check('run crashed before the rename', status /= 0)
      call t%check('a crash before the rename leaves no file under the final name', .not. file_exists(dir//'/crash.h5'))
      call execute_command_line('cd '//dir//' && ls crash.h5.*.part > /dev/null 2>&1', exitstat=status)
      call t%check('... and the complete partial file is kept (nothing lost)', status == 0)
      call execute_command_line('cd '//dir//' && rm -f crash.h5.*.part')
   end subroutine killed_run

   function itoa(i) result(text)
      integer, intent(in) :: i
      character(len=12) :: text
      write (text, '(i0)') i
   end function itoa
end program test_cli_input
