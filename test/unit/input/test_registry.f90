!> The parameter registry: every entry reaches --help, the echo and /config; the reader takes the
!> namelist syntax the studies use (quotes, logicals, repeat counts, comments, several lines); its
!> messages name file, line, group, variable, value and range, all problems at once; the echo
!> reproduces the configuration exactly.
program test_registry
   use mpm_kinds, only: dp
   use mpm_errors, only: error_t
   use mpm_config, only: config_t, read_config, config_parameters, catalog_parameters, config_namelist, used_with, &
                         new_config
   use mpm_scenes, only: scene_slot_t
   use mpm_scene_bar, only: bar_input_t
   use mpm_registry, only: parameter_t, nml_item_t, parse_namelist, apply_items, check_parameter, used_by
   use mpm_output, only: write_config_attributes
   use mpm_hdf5, only: h5_writer_t, h5_exists
   use mpm_testing, only: tester_t, tester, scratch_dir, run_app
   use mpm_testing_runs, only: set_values
   use mpm_sweep, only: sweep_t, sweep_config_t, read_sweep, case_config, sweep_parameters
   use mpm_sweep_output, only: write_sweep_file
   implicit none
   type(tester_t) :: t
   character(len=:), allocatable :: dir

   t = tester('test_registry')
   dir = scratch_dir('registry')
   if (t%case('every_entry_everywhere')) call every_entry_everywhere()
   if (t%case('reader_syntax')) call reader_syntax()
   if (t%case('echo_reproduces')) call echo_reproduces()
   if (t%case('messages')) call messages()
   if (t%case('sweep_over_lists')) call sweep_over_lists()
   if (t%case('text_through_the_registry')) call text_through_the_registry()
   call t%finish()

contains

   subroutine write_text(name, lines)
      character(len=*), intent(in) :: name, lines(:)
      integer :: unit, i
      open (newunit=unit, file=dir//'/'//name, status='replace', action='write')
      do i = 1, size(lines)
         write (unit, '(a)') trim(lines(i))
      end do
      close (unit)
   end subroutine write_text

   !> --help, the echoed namelist and /config each name every registry entry (periods and end_time
   !> exclude each other: one configuration gives each; a scene's own variables appear with its kind,
   !> flip_fraction with transfer = 'blend' and the other transfers' parameters with theirs, a law's with that
   !> law, an integrator's with that integrator).
   subroutine every_entry_everywhere()
      type(config_t), target :: config, by_time, manufactured, composite, impact, plastic, plastic_composite
      type(config_t), target :: implicit, static, xpic, fmpm, asflip
      type(parameter_t), allocatable :: table(:), sweep_table(:)
      type(scene_slot_t), allocatable, target :: slots(:)
      type(sweep_config_t), target :: settings
      character(len=:), allocatable :: help, echo
      integer :: i, status
      config = new_config()
      config%snapshot_count = 1 ! so that the list is echoed too
      by_time = config
      by_time%end_time = 0.01_dp
      by_time%periods = -huge(1.0_dp)
      call set_values(by_time, ["scene.kind='column'"])
      manufactured = config
      call set_values(manufactured, ["scene.kind='manufactured'"])
      composite = config
      call set_values(composite, [character(len=64) :: "scene.kind='composite_bar'", 'scene.lengths=1.0, 1.0', &
                                  'scene.youngs_moduli=1.0e6, 1.0e6', 'scene.densities=1.0e3, 1.0e3'])
      impact = config
      call set_values(impact, [character(len=64) :: "scene.kind='impact'", 'scene.lengths=1.0, 1.0', &
                               'scene.youngs_moduli=1.0e6, 1.0e6', 'scene.densities=1.0e3, 1.0e3', &
                               'scene.velocities=1.0, -1.0'])
      impact%transfer = 'blend' ! (flip_fraction is echoed with the blend alone)
      plastic = config ! a law's own variables appear with that law
      plastic%law = 'elastoplastic'
      plastic_composite = composite
      plastic_composite%law = 'elastoplastic'
      call set_values(plastic_composite, [character(len=64) :: 'material.yield_stresses=1.0e6, 1.0e6', &
                                          'material.hardening_moduli=1.0e6, 1.0e6'])
      implicit = config ! an integrator's own variables appear with that integrator
      implicit%integrator = 'implicit'
      static = config
      static%integrator = 'quasi_static'
      call set_values(static, ["scene.kind='column'"])
      xpic = config
      xpic%transfer = 'xpic'
      fmpm = config
      fmpm%transfer = 'fmpm'
      asflip = config
      asflip%transfer = 'asflip'
      ! (every kind's variables: the registry of the catalog)
      call catalog_parameters(config, slots, table)
      call t%check('the registry has entries', size(table) >= 19)
      call run_app(dir, '--help', status, help)
      echo = config_namelist(config)//config_namelist(by_time)//config_namelist(manufactured)// &
             config_namelist(composite)//config_namelist(impact)//config_namelist(plastic)// &
             config_namelist(plastic_composite)//config_namelist(implicit)//config_namelist(static)// &
             config_namelist(xpic)//config_namelist(fmpm)//config_namelist(asflip)
      call write_attributes(config, dir//'/config.h5')
      call write_attributes(by_time, dir//'/by_time.h5')
      call write_attributes(manufactured, dir//'/manufactured.h5')
      call write_attributes(impact, dir//'/impact.h5')
      call write_attributes(plastic_composite, dir//'/plastic_composite.h5')
      do i = 1, size(table)
         call t%check_contains('--help names '//trim(table(i)%name), help, '    '//trim(table(i)%name)//' = ')
         call t%check_contains('the echo has '//trim(table(i)%name), echo, ' '//trim(table(i)%name)//'=')
         call t%check('/config has '//trim(table(i)%attribute), &
                      h5_exists(dir//'/config.h5', '/config', trim(table(i)%attribute)) .or. &
                      h5_exists(dir//'/by_time.h5', '/config', trim(table(i)%attribute)) .or. &
                      h5_exists(dir//'/manufactured.h5', '/config', trim(table(i)%attribute)) .or. &
                      h5_exists(dir//'/impact.h5', '/config', trim(table(i)%attribute)) .or. &
                      h5_exists(dir//'/plastic_composite.h5', '/config', trim(table(i)%attribute)))
         if (len_trim(table(i)%sweep_list) > 0) call t%check_contains('--help names the sweep list '// &
            trim(table(i)%sweep_list), help, '&sweep '//trim(table(i)%sweep_list))
      end do
      call t%check('/config carries the registry', h5_exists(dir//'/config.h5', '/config', 'parameters'))
      call sweep_parameters(settings, sweep_table)
      do i = 1, size(sweep_table)
         call t%check_contains('--help names sweep.'//trim(sweep_table(i)%name), help, &
                               '    '//trim(sweep_table(i)%name)//' = ')
      end do
      call t%check('an unset end_time is not written', .not. h5_exists(dir//'/config.h5', '/config', &
                                                                                 'end_time'))
   end subroutine every_entry_everywhere

   !> The configuration's /config attributes alone in file `path`.
   subroutine write_attributes(c, path)
      type(config_t), intent(in) :: c
      character(len=*), intent(in) :: path
      type(h5_writer_t) :: h5
      type(error_t), allocatable :: error
      call h5%create(path)
      call h5%group('/config')
      call write_config_attributes(h5, '/config', c)
      call h5%finish(error)
      call t%check('/config written', .not. allocated(error))
   end subroutine write_attributes

   !> The syntax found in the studies' and tests' namelists.
   subroutine reader_syntax()
      type(config_t) :: config
      type(error_t), allocatable :: error
      call write_text('syntax.nml', [character(len=80) :: &
                      '! a comment line', &
                      "&scene kind='vibrating_bar', length=12.5,   ! a comment after a value", &
                      '       youngs_modulus=1.0e9, density=1000, velocity_amplitude=-0.01,', &
                      '       mode=2 /', &
                      "&discretisation scheme='USF' elements=4 particles_per_element=3 /", &
                      '&run end_time=0.01 /', &
                      '&output file="a ""b"" it''s.h5", history=F, snapshot_times=2*0.0, 0.005 /', &
                      '&guards max_cell_move=0.5', '&end'])
      call read_config(dir//'/syntax.nml', config, error)
      call t%check('syntax file read', .not. allocated(error))
      if (allocated(error)) then
         print '(a)', error%message
         return
      end if
      select type (bar => config%scene)
      type is (bar_input_t)
         call t%check('real over lines', bar%youngs_modulus == 1.0e9_dp .and. bar%mode == 2)
         call t%check('integer text for a real', bar%density == 1000.0_dp)
         call t%check('negative real', bar%velocity_amplitude == -0.01_dp)
      class default
         call t%check('the kind read', .false.)
      end select
      call t%check('keywords in lower case', config%scheme == 'usf')
      call t%check('values separated by blanks', config%elements == 4 .and. config%particles_per_element == 3)
      call t%check('end_time given, periods not', config%end_time == 0.01_dp .and. config%periods < 0.0_dp)
      call t%check('doubled quotes in a string', trim(config%file) == 'a "b" it''s.h5', trim(config%file))
      call t%check('logical F', .not. config%history)
      call t%check('repeat count 2*0.0', config%snapshot_count == 3 .and. &
                   all(config%snapshot_times(1:3) == [0.0_dp, 0.0_dp, 0.005_dp]))
      call t%check('guards read, ended by &end', config%max_cell_move == 0.5_dp)
   end subroutine reader_syntax

   !> Reading the echo gives the same configuration, bit for bit.
   subroutine echo_reproduces()
      type(config_t) :: first, second
      type(error_t), allocatable :: error
      integer :: unit
      call write_text('odd.nml', [character(len=120) :: &
                      '&scene length=0.1234567890123456789, youngs_modulus=3.3e-3, density=7.1e-5 /', &
                      "&discretisation scheme='musl', elements=7, dt_fraction=0.333333333333333333 /", &
                      '&run periods=1.1 /', &
                      "&output file='odd.h5', snapshot_times=0.0, 1.0e-9 /"])
      call read_config(dir//'/odd.nml', first, error)
      call t%check('odd values read', .not. allocated(error))
      if (allocated(error)) then
         print '(a)', error%message
         return
      end if
      open (newunit=unit, file=dir//'/echo.nml', status='replace', action='write')
      write (unit, '(a)') config_namelist(first)
      close (unit)
      call read_config(dir//'/echo.nml', second, error)
      call t%check('echo read back', .not. allocated(error))
      if (allocated(error)) return
      call t%check('echo reproduces the reals', first%length == second%length .and. &
                   first%youngs_modulus == second%youngs_modulus .and. first%dt_fraction == second%dt_fraction &
                   .and. first%periods == second%periods)
      call t%check('echo reproduces the rest', first%scheme == second%scheme .and. first%elements == second%elements &
                   .and. first%snapshot_count == second%snapshot_count .and. first%steps == second%steps)
      call t%check('echo of the echo is the echo', config_namelist(first) == config_namelist(second))
   end subroutine echo_reproduces

   !> Messages: file and line, the variable, the value and the range; every problem at once.
   subroutine messages()
      type(config_t) :: config
      type(error_t), allocatable :: error
      call write_text('bad.nml', [character(len=80) :: &
                      '&scene length=25.0,', &
                      '       lenght=3.0 /', &
                      '&discretisation dt_fraction=12.5, elements=0 /', &
                      "&output file='x.h5', history=maybe /", &
                      'stray text', &
                      '&guards energy_growth_limit=1.0 /'])
      call read_config(dir//'/bad.nml', config, error)
      call t%check('bad file refused', allocated(error))
      if (.not. allocated(error)) return
      call t%check_contains('misspelled name with its line', error%message, "bad.nml:2: group &scene: unknown variable 'lenght'")
      call t%check_contains('misspelled name: allowed names', error%message, 'allowed names: kind, length,')
      call t%check_contains('range of dt_fraction', error%message, &
                            'bad.nml:3: discretisation: dt_fraction = 12.5')
      call t%check_contains('range of dt_fraction given', error%message, '0 < dt_fraction <= 10')
      call t%check_contains('range of elements', error%message, 'elements = 0 is out of range; allowed: integer >= 1')
      call t%check_contains('bad logical', error%message, "bad value for 'history': maybe is not a logical")
      call t%check_contains('text outside a group', error%message, "bad.nml:5: text outside a namelist group")
      call t%check_contains('open range', error%message, 'energy_growth_limit = 1.0 is out of range; '// &
                            'allowed: finite real > 1')
      call write_text('long.nml', [character(len=80) :: "&discretisation scheme='usl_with_a_long_tail' /", &
                      '&output snapshot_times=65*0.0 /'])
      call read_config(dir//'/long.nml', config, error)
      call t%check('too long and too many refused', allocated(error))
      if (.not. allocated(error)) return
      call t%check_contains('text longer than the field', error%message, 'is longer than 8 characters')
      call t%check_contains('list longer than allowed', error%message, "'snapshot_times' has 65 values; allowed: up to 64")
   end subroutine messages

   !> The lists of the registry's sweepable variables combine as nested loops, the last list fastest;
   !> every sweepable variable is a /cases column; list values are checked as the variable is.
   subroutine sweep_over_lists()
      type(sweep_t) :: sweep
      type(config_t) :: c
      type(config_t), target :: defaults
      type(scene_slot_t), allocatable, target :: slots(:)
      type(parameter_t), allocatable :: table(:)
      type(error_t), allocatable :: error
      integer :: k, i
      logical :: in_order
      call write_text('sweep.nml', [character(len=100) :: "&output file='sweep.h5' /", &
                      "&sweep modes=1, 2, 3, schemes='usf', 'MUSL',", &
                      '       densities=7800, 1000, min_time=0 /'])
      call read_sweep(dir//'/sweep.nml', sweep, error, 0, 0, 1)
      call t%check('sweep over three lists read', .not. allocated(error))
      if (allocated(error)) then
         print '(a)', error%message
         return
      end if
      call t%check('2 schemes x 2 densities x 3 modes = 12 cases', sweep%total_cases == 12 .and. size(sweep%cases) == 12)
      in_order = .true.
      do k = 1, 12
         c = case_config(sweep, sweep%cases(k))
         ! schemes is the outer loop, densities the middle, modes (the last list) the fastest
         if (c%scheme /= merge('usf ', 'musl', k <= 6)) in_order = .false.
         select type (bar => c%scene)
         type is (bar_input_t)
            if (bar%density /= merge(7800.0_dp, 1000.0_dp, mod((k - 1)/3, 2) == 0)) in_order = .false.
            if (bar%mode /= mod(k - 1, 3) + 1) in_order = .false.
         class default
            in_order = .false.
         end select
         if (c%elements /= 20 .or. c%youngs_modulus /= 200.0e9_dp) in_order = .false.
      end do
      call t%check('cases in loop order, the last list fastest', in_order)
      call write_sweep_file(dir//'/sweep.h5', sweep, error) ! (the namelist's file is relative to the run's folder)
      call t%check('sweep file written', .not. allocated(error))
      defaults = new_config()
      call catalog_parameters(defaults, slots, table) ! (every kind's variables)
      do i = 1, size(table)
         if (len_trim(table(i)%sweep_list) == 0) cycle
         ! the columns of the variables the scene, the law and the integrator use, and only those (a bar
         ! sweep has no gap column, an explicit Hencky one no newton_tolerance or yield_stress)
         call t%check('/cases has the column '//trim(table(i)%attribute)//' exactly when the bar uses it', &
                      h5_exists(dir//'/sweep.h5', '/cases/'//trim(table(i)%attribute)) .eqv. &
                      (used_by(table(i), 'vibrating_bar') .and. used_with(table(i), 'hencky', 'explicit')))
      end do

      call write_text('badsweep.nml', [character(len=100) :: "&scene density=-1.0 /", &
                      "&sweep modes=1, 0, schemes='usf', 'xyz',", &
                      '       dt_fractin=0.1, densities=1.0, , 2.0, shards=0 /'])
      call read_sweep(dir//'/badsweep.nml', sweep, error, 0, 0, 1)
      call t%check('bad sweep refused', allocated(error))
      if (.not. allocated(error)) return
      call t%check_contains('list value out of range', error%message, &
                            'sweep: modes(2) = 0 is out of range; allowed: integer with 1 <= modes(2) <= 1073741823')
      call t%check_contains('list value unknown', error%message, "sweep: schemes(2) = 'xyz' is unknown")
      call t%check_contains('misspelled list: the nearest name, then the lists', error%message, &
                            "badsweep.nml:3: group &sweep: unknown variable 'dt_fractin'; did you mean 'dt_fraction'? "// &
                            "allowed names: scheme,")
      call t%check_contains('gap in a list', error%message, 'densities has a gap')
      call t%check_contains('all at once: settings too', error%message, 'shards = 0 is out of range')
      call t%check_contains('all at once: the base groups too', error%message, &
                            'badsweep.nml:1: scene: density = -1.0 is out of range')
   end subroutine sweep_over_lists

   !> Text that is not a file (as a command-line override `discretisation.elements=40` will be)
   !> goes through the same reader, setter and checks.
   subroutine text_through_the_registry()
      type(config_t), target :: config
      type(parameter_t), allocatable :: table(:)
      type(nml_item_t), allocatable :: items(:)
      character(len=32), allocatable :: groups(:)
      integer, allocatable :: lines(:)
      type(error_t), allocatable :: error
      integer :: i
      config = new_config()
      call config_parameters(config, table)
      call parse_namelist("&discretisation elements=40, scheme='MUSL' /", 'override', items, groups, lines, error)
      call apply_items(table, items, 'discretisation', 'override', error)
      call t%check('override applied', .not. allocated(error) .and. config%elements == 40 .and. config%scheme == 'musl')
      call parse_namelist('&discretisation elements=0 /', 'override', items, groups, lines, error)
      call config_parameters(config, table)
      call apply_items(table, items, 'discretisation', 'override', error)
      do i = 1, size(table)
         if (table(i)%line > 0) call check_parameter(table(i), error, 'override: ')
      end do
      call t%check('bad override refused', allocated(error))
      if (allocated(error)) call t%check_contains('bad override named', error%message, &
                                                  'override: discretisation: elements = 0 is out of range')
   end subroutine text_through_the_registry
end program test_registry
