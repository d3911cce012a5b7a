!> Messages that point at the fix (issue 24, sections 3, 4 and 6): the nearest known name to a
!> misspelled one, a variable named with its group, no follow-on error after an unknown kind, numbers
!> as a person reads them with the file and line, a value refused through a derived quantity blamed
!> on what was typed, encodings named as such, command-line options with their ranges, flip_fraction
!> only with transfer = 'blend', the impact's run length counted from the first contact and a warning
!> when the bars do not meet, a grid margin that cannot overflow, and --help texts made from the
!> registry. Each expectation is a message or a number worked out by hand.
program test_messages
   use, intrinsic :: ieee_arithmetic, only: ieee_value, ieee_quiet_nan
   use mpm_kinds, only: dp
   use mpm_errors, only: error_t
   use mpm_strings, only: str, num_at_least, num_at_most
   use mpm_suggest, only: edit_distance, nearest_words, did_you_mean, printable
   use mpm_config, only: config_t, read_config_text, known_scenes, scene_kinds, scene_kind_t, config_warnings, &
                         config_parameters
   use mpm_registry, only: parameter_t, find_parameter
   use mpm_sweep, only: sweep_t, read_sweep_text
   use mpm_scene, only: margin_for
   use mpm_command_line, only: argument_t, command_line_t, parse_command_line
   use mpm_testing, only: tester_t, tester, scratch_dir, run_app
   implicit none
   type(tester_t) :: t

   t = tester('test_messages')
   if (t%case('suggestions')) call suggestions()
   if (t%case('names_and_groups')) call names_and_groups()
   if (t%case('numbers_and_places')) call numbers_and_places()
   if (t%case('derived_quantities_blame_what_was_typed')) call derived_quantities_blame_what_was_typed()
   if (t%case('encodings')) call encodings()
   if (t%case('flip_fraction_only_with_blend')) call flip_fraction_only_with_blend()
   if (t%case('sweep_values_of_another_integrator')) call sweep_values_of_another_integrator()
   if (t%case('impact_run_length')) call impact_run_length()
   if (t%case('bounds_the_input_may_take')) call bounds_the_input_may_take()
   if (t%case('margins_cannot_overflow')) call margins_cannot_overflow()
   if (t%case('help_made_from_the_registry')) call help_made_from_the_registry()
   if (t%case('command_line')) call command_line()
   call t%finish()

contains

   !> The problems of namelist `text` read as a single run (input 'in.nml'); '' when it is accepted.
   function problems(text, overrides) result(message)
      character(len=*), intent(in) :: text
      character(len=*), intent(in), optional :: overrides(:)
      character(len=:), allocatable :: message
      type(config_t) :: config
      type(error_t), allocatable :: error
      if (present(overrides)) then
         call read_config_text(text, 'in.nml', config, error, overrides=overrides)
      else
         call read_config_text(text, 'in.nml', config, error)
      end if
      message = ''
      if (allocated(error)) message = error%message
   end function problems

   !> The problems of namelist `text` read as a sweep; '' when it is accepted.
   function sweep_problems(text) result(message)
      character(len=*), intent(in) :: text
      character(len=:), allocatable :: message
      type(sweep_t) :: sweep
      type(error_t), allocatable :: error
      call read_sweep_text(text, 'in.nml', sweep, error, 0, 0, 1, [character(len=1) ::])
      message = ''
      if (allocated(error)) message = error%message
   end function sweep_problems

   !> The configuration of an accepted namelist.
   function accepted(text) result(config)
      character(len=*), intent(in) :: text
      type(config_t) :: config
      type(error_t), allocatable :: error
      call read_config_text(text, 'in.nml', config, error)
      call t%check('accepted: '//text, .not. allocated(error))
      if (allocated(error)) print '(a)', error%message
   end function accepted

   subroutine refused(label, message, expected)
      character(len=*), intent(in) :: label, message, expected
      call t%check(label//': refused', len(message) > 0)
      call t%check_contains(label, message, expected)
   end subroutine refused

   !> Edit distances by hand, the nearest names and how they are offered.
   subroutine suggestions()
      call t%check('distance kitten/sitting = 3', edit_distance('kitten', 'sitting') == 3)
      call t%check('distance discretization/discretisation = 1 (one substitution)', &
                   edit_distance('discretization', 'discretisation') == 1)
      call t%check('distance shceme/scheme = 1 (one swap of neighbours)', edit_distance('shceme', 'scheme') == 1)
      call t%check('distance to the empty word = its length', edit_distance('', 'abc') == 3 .and. &
                   edit_distance('abc', '') == 3)
      call t%check('distance of a word to itself = 0', edit_distance('elements', 'elements') == 0)
      call t%check('the nearest of a list', nearest_words('elemnts', 'scheme, elements, shape') == 'elements', &
                   nearest_words('elemnts', 'scheme, elements, shape'))
      call t%check('ties are all offered, in the list''s order', nearest_words('usx', 'usf, usl, musl') == 'usf, usl', &
                   nearest_words('usx', 'usf, usl, musl'))
      call t%check('nothing near: no suggestion', nearest_words('energy_limit', 'scheme, elements') == '')
      call t%check('a word is never its own suggestion', nearest_words('usf', 'usf') == '')
      call t%check('did you mean, one', did_you_mean('discretization', 'scene, discretisation, run', '&') == &
                   '; did you mean &discretisation?', did_you_mean('discretization', 'scene, discretisation, run', '&'))
      call t%check('did you mean, two', did_you_mean('usx', 'usf, usl', "'", "'") == "; did you mean 'usf' or 'usl'?", &
                   did_you_mean('usx', 'usf, usl', "'", "'"))
      call t%check('control characters shown escaped', printable('a'//achar(0)//'b'//achar(9)//achar(27)) == &
                   'a\0b\t\x1b', printable('a'//achar(0)//'b'//achar(9)//achar(27)))
   end subroutine suggestions

   !> Groups and variables: the nearest known name, the group a variable belongs to, &sweep among the
   !> groups; after an unknown kind no message for each of the scene's variables.
   subroutine names_and_groups()
      character(len=:), allocatable :: message
      message = problems('&discretization elements=40 /')
      call refused('misspelled group', message, 'in.nml:1: unknown namelist group &discretization; did you mean '// &
                   '&discretisation? known groups: &scene, &material, &discretisation, &run, &output, &guards, &sweep')
      message = problems('&discretisation elemnts=40 /')
      call refused('misspelled variable', message, "in.nml:1: group &discretisation: unknown variable 'elemnts'; "// &
                   "did you mean 'elements'? allowed names: scheme, elements,")
      message = problems('&run elements=40 /')
      call refused('variable in the wrong group', message, "in.nml:1: group &run: unknown variable 'elements'; "// &
                   "it belongs to &discretisation (allowed names in &run: periods, end_time)")
      message = problems('', ['run.elements=40'])
      call refused('override in the wrong group', message, "command line 'run.elements=40': group &run: unknown "// &
                   "variable 'elements'; it belongs to &discretisation: discretisation.elements=40")
      message = problems('&run elemnts=40 /')
      call refused('misspelled, of another group', message, "did you mean 'elements' of &discretisation?")
      message = problems('', ['discretization.elements=40'])
      call refused('override of a misspelled group', message, "unknown namelist group 'discretization'; did you "// &
                   "mean 'discretisation'?")
      message = problems("&discretisation scheme='usx' /")
      call refused('misspelled keyword', message, "scheme = 'usx' is unknown; did you mean 'usf' or 'usl'? allowed: "// &
                   "'usf', 'usl', 'musl'")
      message = problems("&scene kind='beam', gravity=3.0, lengths=1.0, 2.0, gap=0.5 /")
      call refused('unknown kind', message, "in.nml:1: scene: kind = 'beam' is unknown; allowed:")
      call t%check('unknown kind: no follow-on message for the scene variables', index(message, 'not used by') == 0 &
                   .and. count_lines(message) == 1, message)
      message = sweep_problems("&scene kind='beam' /"//new_line('a')//"&sweep gravity=1.0, 2.0, min_time=0 /")
      call t%check('unknown kind in a sweep: no follow-on message for its lists', index(message, 'not used by') == 0 &
                   .and. count_lines(message) == 1, message)
      message = problems("&scene kind='column', gravity=3.0, gap=0.5 /")
      call refused('a known kind still refuses another kind''s variable', message, &
                   "'gap' is not used by kind = 'column'")
      message = sweep_problems("&sweep gaps=0.1, 0.2, min_time=0 /")
      call refused('a list of another kind''s variable, beside the sweep''s settings', message, "in.nml:1: sweep: "// &
                   "list 'gaps' varies scene: 'gap' is not used by kind = 'vibrating_bar'; it belongs to kind impact")
      message = sweep_problems("&sweep length=1.0, 2.0 /")
      call refused('a variable no sweep list varies', message, "unknown variable 'length'; 'length' of &scene is not "// &
                   "swept")
   end subroutine names_and_groups

   !> Numbers in messages as the terminal shows them (no 0.39496835316262996E-1), with file and line.
   subroutine numbers_and_places()
      character(len=:), allocatable :: message
      message = problems('&discretisation elements=4 /'//new_line('a')//'&output snapshot_times=0.01, 0.5 /')
      ! the bar's end time: 2 periods of 2 pi/omega, omega = pi c/(2L), c = sqrt(200e9/7800): 8 L/c = 0.0395 s
      call refused('snapshot after the end', message, 'in.nml:2: output: snapshot_times(2) = 0.5 s is after the end '// &
                   'of the run at 0.0395 s; allowed: times within the run, 0 to 0.0395 s')
      call t%check('no long numbers in the message', index(message, 'E-') == 0 .and. index(message, '9999') == 0, &
                   message)
      message = problems("&scene kind='impact', lengths=1.0, 1.0, youngs_moduli=1e9, 4e9, densities=1000, 1000, "// &
                         "velocities=1, -1 /")
      ! impedances sqrt(1e9 1000) = 1e6 and sqrt(4e9 1000) = 2e6
      call refused('impedances readable', message, 'given 1e+06 and 2e+06 kg/(m^2 s)')
      message = problems("&scene kind='manufactured', length=1.0, amplitude=0.2 /")
      call refused('manufactured amplitude readable', message, "amplitude = 0.2 m, length = 1 m give 1.257; "// &
                   "allowed: amplitude < 0.1592 m")
   end subroutine numbers_and_places

   !> A value refused through a quantity derived from it names what was typed.
   subroutine derived_quantities_blame_what_was_typed()
      character(len=:), allocatable :: message
      message = problems("&scene kind='composite_bar', lengths=1.0, 1.0, youngs_moduli=1e300, 1e6, "// &
                         "densities=1000, 1000 /")
      ! c1 = sqrt(1e300/1000) = 3.162e148 m/s against c2 = sqrt(1e6/1000) = 31.62 m/s: 1e147 times
      call refused('composite youngs_moduli = 1e300', message, "in.nml:1: scene: youngs_moduli(1) = 1e300 Pa and "// &
                   "densities(1) = 1000 kg/m^3 give segment 1 a wave speed of 3.162e+148 m/s, 1e+147 times segment "// &
                   "2's (31.62 m/s)")
      call refused('composite youngs_moduli = 1e300: still the step count', message, 'allowed: at most 2147483646 steps')
      message = problems("&scene kind='impact', lengths=1.0, 1.0, youngs_moduli=1e9, 1e9, densities=1000, 1000, "// &
                         "velocities=1, -1, gap=1e300 /")
      ! dx = (1 + 1e300 + 1)/20 = 5e298 m; each bar at least half a cell: gap <= 2*1*20 - 2 = 38 m
      call refused('impact gap = 1e300', message, "in.nml:1: scene: gap = 1e300 m with lengths = 1, 1 m on elements "// &
                   "= 20 gives cells of dx = (lengths(1) + gap + lengths(2))/elements = 5e+298 m")
      call refused('impact gap = 1e300: the allowed gap', message, 'gap <= 38 m at elements = 20')
      call t%check('impact gap = 1e300: periods not blamed', index(message, 'periods') == 0, message)
      message = problems("&scene kind='composite_bar', lengths=1.0, 1.0, youngs_moduli=16e6, 1e6, "// &
                         "densities=1000, 1000, drive_velocity=1e10 /")
      ! T = 2 (1/126.5 + 1/31.62) = 0.07906 s; 4 v T = 3.162e9 m over dx = 0.1 m: 3.16e10 cells > 1e8
      call refused('composite drive_velocity = 1e10', message, "in.nml:1: scene: drive_velocity = 1e10 m/s moves "// &
                   "the bar's free end by up to 4 v T = 3.162e+09 m")
      call refused('composite drive_velocity = 1e10: the allowed range', message, &
                   'allowed: at most 1e8 cells, drive_velocity <= 3.162e+07 m/s')
      message = problems("&scene kind='impact', lengths=1.0, 1.0, youngs_moduli=1e9, 1e9, densities=1000, 1000, "// &
                         "velocities=1e10, -1 / &discretisation elements=8 /")
      call refused('impact velocities = 1e10', message, "scene: velocities = 1e10, -1 m/s move the bars' outer ends")
      message = problems("&scene kind='composite_bar', lengths=1.0, 1.0, youngs_moduli=16e6, 1e6, "// &
                         "densities=1000, 1000, drive_velocity=1e4 /")
      call t%check('composite drive_velocity = 1e4 runs (the J <= 0 guard stops it)', len(message) == 0, message)
   end subroutine derived_quantities_blame_what_was_typed

   !> A byte-order mark, UTF-16 and NUL bytes are named as such.
   subroutine encodings()
      character(len=:), allocatable :: message, utf16
      integer :: k
      character(len=*), parameter :: text = '&discretisation elements=3 /'
      message = problems(char(239)//char(187)//char(191)//text)
      call refused('UTF-8 byte-order mark', message, 'in.nml:1: the input starts with a UTF-8 byte-order mark '// &
                   '(bytes EF BB BF)')
      call t%check('UTF-8 byte-order mark: the rest is read (no text outside a group)', &
                   index(message, 'text outside') == 0, message)
      utf16 = ''
      do k = 1, len(text)
         utf16 = utf16//text(k:k)//achar(0)
      end do
      message = problems(char(255)//char(254)//utf16)
      call refused('UTF-16 with its mark', message, 'in.nml:1: the input is UTF-16 text (it starts with the '// &
                   'byte-order mark FF FE)')
      message = problems(utf16)
      call refused('UTF-16 without a mark', message, 'in.nml:1: the input looks like UTF-16 text')
      call t%check('UTF-16: one message, not one per character', count_lines(message) == 1, message)
      message = problems("&output file='out"//achar(0)//".h5' /")
      call refused('NUL in the output file name', message, "in.nml:1: output: bad value for 'file': 'out\0.h5' holds "// &
                   "a NUL byte (\0, character code 0)")
      message = problems('&discretisation elements=3'//achar(0)//' /')
      call refused('NUL after a number', message, "bad value for 'elements': '3\0' holds a NUL byte")
      message = problems(achar(0)//achar(0)//achar(0)//achar(0))
      call refused('NUL bytes only', message, "in.nml:1: text outside a namelist group: '\0\0\0\0' (NUL bytes: "// &
                   "not a text file?)")
      call t%check('no raw NUL byte in any message', index(message, achar(0)) == 0)
   end subroutine encodings

   !> flip_fraction is used by transfer = 'blend' alone: given otherwise it is refused naming both; in a
   !> sweep, a list of it needs 'blend' among the transfers, and several values of it 'blend' alone.
   subroutine flip_fraction_only_with_blend()
      character(len=:), allocatable :: message
      type(config_t) :: config
      character(len=*), parameter :: small = '&discretisation elements=4 / &run periods=0.25 / '
      message = problems('&discretisation flip_fraction=0.5 /')
      call refused('flip_fraction with FLIP', message, "in.nml:1: discretisation: flip_fraction = 0.5 is used only "// &
                   "with transfer = 'blend', not with transfer = 'flip'; allowed: flip_fraction with transfer = "// &
                   "'blend', or no flip_fraction")
      message = problems("&discretisation transfer='apic' /", ['discretisation.flip_fraction=0.3'])
      call refused('flip_fraction with APIC on the command line', message, "command line 'discretisation."// &
                   "flip_fraction=0.3': discretisation: flip_fraction = 0.3 is used only with transfer = 'blend', "// &
                   "not with transfer = 'apic'")
      config = accepted("&discretisation flip_fraction=0.5, transfer='blend' /")
      call t%check('flip_fraction with blend: read', config%flip_fraction == 0.5_dp)
      config = accepted("&discretisation transfer='pic' /")
      call t%check('the echo of a PIC run leaves flip_fraction out (it must read back)', &
                   index(echo_of(config), 'flip_fraction') == 0, echo_of(config))
      config = accepted("&discretisation transfer='blend', flip_fraction=0.25 /")
      call t%check('the echo of a blend run keeps flip_fraction', index(echo_of(config), 'flip_fraction=0.25') > 0, &
                   echo_of(config))
      message = sweep_problems(small//"&sweep transfer='flip', 'pic', flip_fraction=0.3, 0.5, min_time=0 /")
      call refused('sweep: flip_fraction list without blend', message, "in.nml:1: sweep: flip_fraction (the list) is "// &
                   "used only with transfer = 'blend', not with the sweep's transfer list ('flip', 'pic')")
      message = sweep_problems(small//"&sweep transfer='flip', 'blend', flip_fraction=0.3, 0.5, min_time=0 /")
      call refused('sweep: several flip_fractions beside flip', message, "flip_fraction (the list) has 2 values, but "// &
                   "the sweep's transfer 'flip' does not use flip_fraction: each of its cases would run once per "// &
                   "value, alike")
      message = sweep_problems("&discretisation elements=4, flip_fraction=0.3 / &run periods=0.25 / "// &
                               "&sweep transfer='flip', 'apic', min_time=0 /")
      call refused('sweep: a given flip_fraction no case uses', message, "in.nml:1: discretisation: flip_fraction = "// &
                   "0.3 is used only with transfer = 'blend', not with the sweep's transfer list ('flip', 'apic')")
      message = sweep_problems(small//"&sweep transfer='blend', flip_fraction=0.3, 0.5, 1.0, min_time=0 /")
      call t%check('sweep: flip_fractions with blend alone: accepted', len(message) == 0, message)
      message = sweep_problems("&discretisation elements=4, flip_fraction=0.3 / &run periods=0.25 / "// &
                               "&sweep transfer='flip', 'blend', min_time=0 /")
      call t%check('sweep: a given flip_fraction the blend cases use: accepted', len(message) == 0, message)
      message = sweep_problems(small//"&sweep transfer='flip', 'blend', flip_fraction=0.3, min_time=0 /")
      call t%check('sweep: one flip_fraction beside flip and blend: accepted', len(message) == 0, message)
      block
         type(sweep_t) :: sweep
         type(error_t), allocatable :: error
         call read_sweep_text("&discretisation elements=4, flip_fraction=0.3 / &run periods=0.25 / "// &
                              "&sweep transfer='flip', 'blend', min_time=0 /", 'in.nml', sweep, error, 0, 0, 1, &
                              [character(len=1) ::])
         call t%check('sweep: base flip_fraction for the blend cases read', .not. allocated(error))
         call t%check_contains('sweep: the base echo keeps a flip_fraction the blend cases use (base transfer '// &
                               'flip)', echo_of(sweep%base), 'flip_fraction=0.29999999999999999')
      end block
   end subroutine flip_fraction_only_with_blend

   !> A sweep's list of a variable its integrator does not use is refused at the cases whose value is not
   !> the default (the default is what a run of that integrator holds anyway).
   subroutine sweep_values_of_another_integrator()
      character(len=:), allocatable :: message
      message = sweep_problems("&scene kind='column' / &discretisation integrator='quasi_static' / "// &
                               "&sweep dt_fractions=0.1, 0.2, min_time=0 /")
      call refused('sweep: a dt_fraction other than the default, with quasi_static', message, "sweep case 2 "// &
                   "(dt_fraction=0.20000000000000001): discretisation: 'dt_fraction' is not used by integrator = "// &
                   "'quasi_static'; it belongs to integrator explicit, implicit")
      call t%check('sweep: the default dt_fraction, with quasi_static: not refused', &
                   index(message, 'sweep case 1 ') == 0, message)
      ! dt_fraction's bound is the case's integrator's (10 explicit, 1e8 implicit), not the base's nor the
      ! case's before (cases 2 implicit, 3 explicit, 4 implicit)
      message = sweep_problems("&discretisation elements=4, integrator='implicit' / &run periods=4 / "// &
                               "&sweep integrator='explicit', 'implicit', dt_fractions=0.5, 50, min_time=0 /")
      call refused('sweep: dt_fraction 50 with the explicit integrator (the base implicit)', message, &
                   "sweep case 3 (dt_fraction=50.000000000000000, integrator='explicit'): discretisation: "// &
                   "dt_fraction = 50.0 is out of range; allowed: finite real with 0 < dt_fraction <= 10")
      call t%check('sweep: dt_fraction 50 with the implicit integrator: not refused', &
                   index(message, 'sweep case 4 ') == 0, message)
   end subroutine sweep_values_of_another_integrator

   function echo_of(config) result(text)
      use mpm_config, only: config_namelist
      type(config_t), intent(in) :: config
      character(len=:), allocatable :: text
      text = config_namelist(config)
   end function echo_of

   !> A lower bound a message says is one the input may take. The bar on one element at half of dx/c: dt
   !> = 0.5 L/c against the period 4 L/c, so periods >= 0.125 (0.12500000000000003 in floating point):
   !> said as 0.125 it was itself refused; said rounded up, 0.1251, it is accepted. The same for the
   !> run's end_time (>= dt) and for num_at_least and num_at_most by hand.
   subroutine bounds_the_input_may_take()
      character(len=*), parameter :: one_element = "&discretisation elements=1, particles_per_element=1, "// &
                                                   "dt_fraction=0.5 / "
      character(len=:), allocatable :: message, bound
      real(dp) :: value
      integer :: at, stat
      message = problems(one_element//"&run periods=0.125 /")
      call refused('periods = 0.125 on one element at 0.5 dx/c', message, 'allowed: periods >= 0.1251')
      message = problems(one_element//"&run periods=0.1251 /")
      call t%check('... the bound said, periods = 0.1251, is accepted', len(message) == 0, message)
      ! end_time: dt = 0.5*25/sqrt(200e9/7800) = 2.468727e-3 s (four digits: 2.469e-3, up from 2.4687...)
      message = problems(one_element//"&run end_time=1e-3 /")
      at = index(message, 'allowed: end_time >= ')
      call t%check('end_time = 1e-3 refused with its bound', at > 0, message)
      if (at > 0) then
         bound = message(at + len('allowed: end_time >= '):)
         bound = bound(1:index(bound, ' ') - 1)
         read (bound, *, iostat=stat) value
         call t%check('... the bound said ('//bound//') is at least dt', stat == 0 .and. value >= &
                      0.5_dp*25.0_dp/sqrt(200.0e9_dp/7800.0_dp), bound)
         message = problems(one_element//"&run end_time="//bound//" /")
         call t%check('... and end_time = '//bound//' is accepted', len(message) == 0, message)
      end if
      call t%check('num_at_least(0.12500000000000003, 4) = 0.1251', num_at_least(0.125_dp + 3.0e-17_dp, 4) == &
                   '0.1251', num_at_least(0.125_dp + 3.0e-17_dp, 4))
      call t%check('num_at_least(0.125, 4) = 0.125 (exact: kept)', num_at_least(0.125_dp, 4) == '0.125')
      call t%check('num_at_least(2.46871e-3, 4) = 2.469e-03', num_at_least(2.46871e-3_dp, 4) == '2.469e-03', &
                   num_at_least(2.46871e-3_dp, 4))
      call t%check('num_at_most(2.46879e-3, 4) = 2.468e-03', num_at_most(2.46879e-3_dp, 4) == '2.468e-03', &
                   num_at_most(2.46879e-3_dp, 4))
      call t%check('num_at_most(38, 4) = 38 (exact: kept)', num_at_most(38.0_dp, 4) == '38')
      call t%check('num_at_least(-1.00001, 4) = -1', num_at_least(-1.00001_dp, 4) == '-1', &
                   num_at_least(-1.00001_dp, 4))
      call t%check('num_at_least(1.5e-300, 2) >= 1.5e-300', num_at_least(1.5e-300_dp, 2) == '1.5e-300', &
                   num_at_least(1.5e-300_dp, 2))
   end subroutine bounds_the_input_may_take

   !> The impact's periods count from the first contact; a run whose bars do not meet is warned.
   subroutine impact_run_length()
      type(config_t) :: config
      character(len=*), parameter :: bars = "&scene kind='impact', lengths=1.0, 1.0, youngs_moduli=1e9, 1e9, "// &
                                            "densities=1000, 1000, "
      character(len=:), allocatable :: warning
      ! c = sqrt(1e9/1000) = 1000 m/s: the period 2 L/c = 2 ms; 0.01 m closing at 2 m/s meet at 5 ms
      config = accepted(bars//"velocities=1, -1, gap=0.01 /")
      call t%check_close('impact: periods count from the first contact (5 ms + 2 x 2 ms)', config%final_time, &
                         0.009_dp, rtol=1.0e-14_dp)
      call t%check('impact that meets: no warning', len(config_warnings(config)) == 0, config_warnings(config))
      config = accepted(bars//"velocities=1, -1, gap=0.0 /")
      call t%check_close('impact without a gap: 2 periods from t = 0', config%final_time, 0.004_dp, rtol=1.0e-14_dp)
      config = accepted(bars//"velocities=1, -1, gap=0.01 / &run end_time=0.0008 /")
      warning = config_warnings(config)
      call t%check_contains('impact ending before contact: warned', warning, 'the bars do not meet before the end '// &
                            'of the run: gap = 0.01 m closing at 2 m/s first touches at t = 5e-03 s, after the end '// &
                            'time 8e-04 s')
      config = accepted(bars//"velocities=-1, 1, gap=0.01 /")
      call t%check_contains('impact of bars moving apart: warned', config_warnings(config), &
                            'the bars never meet: velocities = -1, 1 m/s')
      call t%check_close('impact of bars moving apart: periods from t = 0', config%final_time, 0.004_dp, &
                         rtol=1.0e-14_dp)
      config = accepted("&scene kind='column' / &run end_time=0.0008 /")
      call t%check('other scenes: no warning', len(config_warnings(config)) == 0)
   end subroutine impact_run_length

   !> The automatic margin (reach in cells, rounded up, plus two) stays an integer for any reach.
   subroutine margins_cannot_overflow()
      call t%check('margin: 10.5 cells -> 11 + 2', margin_for(10.5_dp, 1.0_dp, -1) == 13)
      call t%check('margin: requested wins', margin_for(1.0e300_dp, 1.0_dp, 5) == 5)
      call t%check('margin: 3e10 cells capped at 1e9 + 2, not negative', margin_for(3.0e9_dp, 0.1_dp, -1) == &
                   1000000002, str(margin_for(3.0e9_dp, 0.1_dp, -1)))
      call t%check('margin: 1e300 cells capped', margin_for(1.0e300_dp, 1.0_dp, -1) == 1000000002)
      call t%check('margin: NaN capped', margin_for(ieee_value(1.0_dp, ieee_quiet_nan), 1.0_dp, -1) == 1000000002)
   end subroutine margins_cannot_overflow

   !> --help's texts of kind and periods are made from the scene table, which covers every known scene.
   subroutine help_made_from_the_registry()
      type(config_t), target :: config
      type(parameter_t), allocatable :: table(:)
      type(scene_kind_t), allocatable :: kinds(:)
      character(len=:), allocatable :: help, kind_help, periods_help, rest, scene
      integer :: k, comma, status
      kinds = scene_kinds()
      call config_parameters(config, table)
      kind_help = trim(table(find_parameter(table, 'scene', 'kind'))%help)
      periods_help = trim(table(find_parameter(table, 'run', 'periods'))%help)
      rest = known_scenes()//','
      do
         comma = index(rest, ',')
         if (comma == 0) exit
         scene = trim(adjustl(rest(1:comma - 1)))
         call t%check('scene table has '//scene, any(kinds%name == scene))
         call t%check_contains('kind''s help describes '//scene, kind_help, "'"//scene//"' ")
         call t%check_contains('periods'' help gives the period of '//scene, periods_help, scene//': ')
         rest = rest(comma + 1:)
      end do
      call t%check('no scene table row without a scene', size(kinds) == count_commas(known_scenes()) + 1)
      call t%check_contains('periods mentions the composite bar', periods_help, 'composite_bar: sum L_i/c_i')
      call run_app(scratch_dir('messages'), '--help', status, help)
      call t%check_contains('--help: kind lists the impact', help, "'impact' two bars colliding")
      call t%check_contains('--help: flip_fraction says it needs blend', help, "transfer = 'blend' only")
      call t%check('--help points at docs/, not the README', index(help, 'README') == 0)
   end subroutine help_made_from_the_registry

   !> The command line: an override without its group, options out of range.
   subroutine command_line()
      call expect_refusal('bare elements=40', [arg('elements=40')], "argument 'elements=40' is neither a file nor "// &
                          "an override; an override names its group: discretisation.elements=40")
      call expect_refusal('bare elements=40 after a file', [arg('in.nml'), arg('elements=40')], &
                          "too many arguments: 'elements=40' after the input file 'in.nml' (an override names its "// &
                          "group: discretisation.elements=40)")
      call expect_refusal('bare list of a sweep', [arg('schemes=usf,usl')], 'sweep.schemes=usf,usl')
      call expect_refusal('bare sweep setting', [arg('min_time=0')], 'sweep.min_time=0')
      call expect_refusal('bare misspelled', [arg('elemnts=40')], 'did you mean the override discretisation.elements=40?')
      call expect_refusal('--threads -1', [arg('--threads'), arg('-1')], &
                          '--threads -1 is out of range; allowed: 0 (all cores) to 4096')
      call expect_refusal('--threads=-1', [arg('--threads=-1')], '--threads -1 is out of range; allowed: 0')
      call expect_refusal('--threads beyond the integers', [arg('--threads=99999999999')], '--threads 99999999999 is '// &
                          'out of range')
      call expect_refusal('--threads word', [arg('--threads=two')], "--threads 'two' is not a whole number; allowed: "// &
                          "0 (all cores) to 4096")
      call expect_refusal('--shard -1/2', [arg('--shard=-1/2')], '--shard -1/2 is out of range: I = -1 must be >= 1; '// &
                          'allowed: I/N, whole numbers with 1 <= I <= N')
      call expect_refusal('--shard 1/0', [arg('--shard'), arg('1/0')], '--shard 1/0 is out of range: N = 0 must be >= 1')
      call expect_refusal('--shard 3/2', [arg('--shard=3/2')], '--shard 3/2 is out of range: I = 3 must be <= N = 2')
      call expect_refusal('--shard x/2', [arg('--shard=x/2')], '--shard x/2 is malformed')
      call expect_refusal('--help with more', [arg('--help'), arg('in.nml')], "'--help' takes no other arguments")
      call expect_refusal('merge alone', [arg('merge'), arg('a.h5')], 'usage: mpm1d merge OUT.h5 SHARD1.h5')
      block
         type(command_line_t) :: cl
         type(error_t), allocatable :: error
         call parse_command_line([arg('-q'), arg('in.nml'), arg('discretisation.elements=40'), arg('--threads=3'), &
                                  arg('--shard'), arg('2/5')], cl, error)
         call t%check('a good command line read', .not. allocated(error) .and. cl%quiet .and. cl%has_input .and. &
                      cl%threads == 3 .and. cl%shard == 2 .and. cl%shards == 5 .and. size(cl%overrides) == 1)
         if (allocated(cl%input)) call t%check('the input', cl%input == 'in.nml')
      end block
   end subroutine command_line

   subroutine expect_refusal(label, args, expected)
      character(len=*), intent(in) :: label, expected
      type(argument_t), intent(in) :: args(:)
      type(command_line_t) :: cl
      type(error_t), allocatable :: error
      call parse_command_line(args, cl, error)
      call t%check(label//': refused', allocated(error))
      if (allocated(error)) call t%check_contains(label, error%message, expected)
   end subroutine expect_refusal

   function arg(text) result(a)
      character(len=*), intent(in) :: text
      type(argument_t) :: a
      a%text = text
   end function arg

   integer function count_lines(text)
      character(len=*), intent(in) :: text
      integer :: i
      count_lines = 0
      if (len(text) > 0) count_lines = 1
      do i = 1, len(text)
         if (text(i:i) == new_line('a')) count_lines = count_lines + 1
      end do
   end function count_lines

   integer function count_commas(text)
      character(len=*), intent(in) :: text
      integer :: i
      count_commas = 0
      do i = 1, len(text)
         if (text(i:i) == ',') count_commas = count_commas + 1
      end do
   end function count_commas
end program test_messages
