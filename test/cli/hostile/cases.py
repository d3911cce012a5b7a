"""The hostile-input cases of mpm1d (issue 18's six classes and issue 16's defects), as data.

Each case is a dict:
  name      unique name
  cls       its class: '1 not understood', '2 values changed', '3 messages', '4 paths', '5 scale',
            '6 signals', '7 survival' (a full disk), '8 laws and integrators', or 'i16.N' for defect N of
            issue 16, section 3
  input     text (or bytes) written to in.nml (None: no file)
  files     further files {name: text or bytes} written before the run
  args      the arguments ('{exe}' is the executable); default ['in.nml']
  env       environment added; stdin: text given on standard input
  setup     bash run in the case's folder before the run; shell: bash run instead of mpm1d ($MPM1D; $PYTHON
            is the suite's Python, with h5py)
  exit      the expected exit code (README: 0 success, 1 a guard stopped the run, 2 bad input, 3 output)
  pattern   a regular expression the output (standard output + standard error) must contain
  not_pattern  one it must not contain
  exists / absent  globs of files that must / must not exist afterwards
  rel_error the expected /summary/relative_error of o.h5 (a number, or '@name': that of reference case name)
  ref       this case is a reference others compare with (run first)
"""

CASES = []

#: a tiny bar run: 4 elements, a quarter period (10 steps), output o.h5
SMALL = dict(scene='', discretisation='elements=4', run='periods=0.25', output="file='o.h5'", guards='')
REFUSED = ['o.h5']


def nml(**groups):
    """Namelist text: the tiny run with `groups` replacing (text) or dropping (None) its groups."""
    parts = dict(SMALL)
    parts.update(groups)
    return ''.join(f'&{g} {v} /\n' for g, v in parts.items() if v is not None)


def add(name, cls, exit, pattern=None, **kw):
    case = dict(name=name, cls=cls, exit=exit, pattern=pattern)
    case.setdefault('input', None)
    case.update(kw)
    if exit == 2 and 'absent' not in case and not case.get('shell'):
        case['absent'] = REFUSED
    CASES.append(case)


def refused(name, cls, text, pattern, **kw):
    add(name, cls, 2, pattern, input=text, **kw)


GROUPS = ['scene', 'discretisation', 'run', 'output', 'guards']

# ---------------------------------------------------------------- 1: input that is not understood
C1 = '1 not understood'
refused('empty_file', C1, '', r"in\.nml.*(empty|no namelist group)")
refused('blank_file', C1, '   \n\n\t\n', r"in\.nml.*(empty|no namelist group)")
refused('comment_only', C1, '! nothing but a comment\n! and another\n', r"in\.nml.*no namelist group")
refused('crlf_comment_only', C1, '! comment\r\n\r\n', r"in\.nml.*no namelist group")
refused('empty_stdin', C1, None, r"standard input.*(empty|no namelist group)", args=['-'], stdin='')
refused('comment_stdin', C1, None, r"standard input.*no namelist group", args=['-'], stdin='! hi\n')
refused('plain_words', C1, 'hello world\n', r"in\.nml:1: text outside a namelist group")
refused('json', C1, '{"scene": {"length": 3.0}}\n', r"in\.nml:1: text outside")
refused('yaml', C1, 'scene:\n  length: 3.0\n', r"in\.nml:1: text outside")
refused('toml', C1, '[scene]\nlength = 3.0\n', r"in\.nml:1: text outside")
refused('ini_equals', C1, 'length = 3.0\n', r"in\.nml:1: text outside")
refused('utf16_bom', C1, '\ufeff&scene length=3.0 /\n'.encode('utf-16'), r"in\.nml:1: the input is UTF-16 text")
refused('utf16_le', C1, '&scene length=3.0 /\n'.encode('utf-16-le'), r"in\.nml:1:")
refused('utf8_bom', C1, '\ufeff&scene length=3.0 /\n'.encode('utf-8'), r"in\.nml:1: the input starts with a UTF-8 byte-order mark")
refused('gzip_bytes', C1, b'\x1f\x8b\x08\x00\x00\x00\x00\x00\x00\x03\xcbH\xcd\xc9\xc9\x07\x00', r"in\.nml:1: text outside")
refused('elf_header', C1, b'\x7fELF\x02\x01\x01\x00' + bytes(range(1, 60)), r"in\.nml:1: text outside")
refused('zip_header', C1, b'PK\x03\x04\x14\x00\x00\x00' + b'x' * 30, r"in\.nml:1: text outside")
refused('png_header', C1, b'\x89PNG\r\n\x1a\n' + b'\x00' * 20, r"in\.nml:1: text outside")
refused('nul_only', C1, b'\x00\x00\x00\x00', r"in\.nml:1: text outside")
refused('nul_after_value', C1, b"&discretisation elements=3\x00 /\n", r"'elements'")
refused('nul_in_name', C1, b"&discretisation elem\x00ents=3 /\n", r"in\.nml:1:")
refused('nul_before_group', C1, b"\x00&discretisation elements=3 /\n", r"in\.nml:1: text outside")
refused('dollar_group', C1, '$discretisation elements=3 $end\n', r"in\.nml:1: text outside")
refused('dollar_end_after_amp', C1, '&discretisation elements=3 $end\n', r"in\.nml:1:")
refused('ampersand_space', C1, '& scene length=3.0 /\n', r"in\.nml:1: .*group name")
refused('ampersand_tab', C1, '&\tscene length=3.0 /\n', r"in\.nml:1: .*group name")
refused('ampersand_alone', C1, '&\n', r"in\.nml:1: .*group name")
refused('unterminated_group', C1, '&scene length=3.0\n', r"in\.nml:1: group &scene: not terminated")
refused('two_groups_no_slash', C1, '&scene length=3.0\n&run periods=1 /\n', r"not terminated by '/' before")
refused('slash_only', C1, '/\n', r"in\.nml:1: text outside")
refused('value_without_name', C1, '&scene 3.0 /\n', r"in\.nml:1: group &scene: value '3\.0' without a name")
refused('unknown_group', C1, '&scen length=3 /\n', r"in\.nml:1: unknown namelist group &scen")
refused('group_twice', C1, '&scene length=3 /\n&scene density=2 /\n', r"in\.nml:2: group &scene is given twice")
for g in GROUPS:
    body = {'scene': 'length=3.0', 'discretisation': 'elements=4', 'run': 'periods=0.25',
            'output': "file='o.h5'", 'guards': 'max_cell_move=0.5'}[g]
    refused(f'no_ampersand_{g}', C1, f'{g} {body} /\n', r"in\.nml:1: text outside a namelist group")
    refused(f'text_before_{g}', C1, f'run this please\n&{g} {body} /\n', r"in\.nml:1: text outside")
    refused(f'text_after_{g}', C1, f'&{g} {body} /\nthanks\n', r"in\.nml:2: text outside")
    refused(f'same_line_after_{g}', C1, f'&{g} {body} / trailing words\n', r"in\.nml:1: text outside")
    refused(f'amp_space_{g}', C1, f'& {g} {body} /\n', r"in\.nml:1: .*group name")
    refused(f'upper_dollar_{g}', C1, f'${g.upper()} {body} $END\n', r"in\.nml:1: text outside")
    refused(f'after_5000_columns_junk_{g}', C1, ' ' * 5000 + f'x&{g} {body} /\n', r"in\.nml:1: text outside")
# a group after column 4096 is read (not lost)
add('group_after_column_4096', C1, 0, r"elements=3,", input=' ' * 5000 + "&discretisation elements=3 /\n"
    "&run periods=0.25 / &output file='o.h5' /\n", exists=['o.h5'])
add('group_after_column_70000', C1, 0, r"elements=3,", input=' ' * 70000 + "&discretisation elements=3 /\n"
    "&run periods=0.25 / &output file='o.h5' /\n", exists=['o.h5'])
add('crlf_file_read', C1, 0, r"elements=3,", input="&discretisation elements=3 /\r\n&run periods=0.25 /\r\n"
    "&output file='o.h5' /\r\n", exists=['o.h5'])
add('tabs_read', C1, 0, r"elements=3,", input="&discretisation\telements=3\t/\n&run periods=0.25 /\n"
    "&output file='o.h5' /\n", exists=['o.h5'])
add('comments_read', C1, 0, r"elements=3,", input="! a comment\n&discretisation elements=3 ! three\n/\n"
    "&run periods=0.25 / ! after\n&output file='o.h5' /\n", exists=['o.h5'])
add('end_terminator_read', C1, 0, r"elements=3,", input="&discretisation elements=3 &end\n&run periods=0.25 /\n"
    "&output file='o.h5' /\n", exists=['o.h5'])
add('no_input_runs_default_with_notice', C1, 0, r"no input file given; running the built-in verification case",
    args=['discretisation.elements=4', 'run.periods=0.25', 'output.file=o.h5'], exists=['o.h5'])

# ---------------------------------------------------------------- 2: values silently changed
C2 = '2 values changed'
TEXTS = {'scheme': ('discretisation', 8, 'usl'), 'shape': ('discretisation', 8, 'linear'),
         'transfer': ('discretisation', 8, 'flip'), 'kernels': ('discretisation', 8, 'auto'),
         'formulation': ('discretisation', 8, 'updated'),
         'kind': ('scene', 32, 'vibrating_bar')}
for var, (g, width, word) in TEXTS.items():
    refused(f'long_{var}', C2, nml(**{g: f"{var}='{word}{'x' * (width + 1)}'"}),
            rf"'{var}'.*longer than {width} characters")
    refused(f'word_then_text_{var}', C2, nml(**{g: f"{var}='{word}   and more'"}), rf"{var}")
    refused(f'word_then_spaces_{var}', C2, nml(**{g: f"{var}='{word}{' ' * 40}x'"}), rf"{var}")
    refused(f'unquoted_{var}', C2, nml(**{g: f"{var}={word}"}), rf"'{var}'.*not quoted text")
    refused(f'empty_{var}', C2, nml(**{g: f"{var}=''"}), rf"{var}")
refused('long_file_1025', C2, nml(output=f"file='{'a' * 1022}.h5'"), r"'file'.*longer than 1024 characters")
refused('long_file_5000', C2, nml(output=f"file='{'a' * 4997}.h5'"), r"'file'.*longer than 1024 characters")
refused('file_text_after_name', C2, nml(output="file='o.h5' 'p.h5'"), r"'file' takes one value")
BAD_REALS = {'dash': '-', 'plus': '+', 'dot': '.', 'e_alone': 'e5', 'two_dots': '1.0.0', 'bare_e': '1e',
             'double_sign': '--1', 'hex': '0x10', 'dash_dot': '-.', 'd_alone': 'd', 'sign_e': '-e3',
             'trailing_letter': '1.5m', 'comma_decimal': "1'5"}
REALS = {'length': 'scene', 'youngs_modulus': 'scene', 'density': 'scene', 'velocity_amplitude': 'scene',
         'dt_fraction': 'discretisation', 'flip_fraction': 'discretisation', 'periods': 'run',
         'energy_growth_limit': 'guards', 'max_cell_move': 'guards'}
for var, g in REALS.items():
    for tag, token in BAD_REALS.items():
        refused(f'real_{var}_{tag}', C2, nml(**{g: f'{var}={token}'}), rf"{var}")
for var, g in {'end_time': 'run', 'periods': 'run'}.items():
    other = 'end_time' if var == 'periods' else 'periods'
    for value in ['-1.7976931348623157e308', '-1.7976931348623157d308', '-huge']:
        tag = value.replace('.', '_').replace('-', 'm')
        refused(f'sentinel_{var}_{tag}', C2, nml(run=f'{var}={value}'), rf"{var}", not_pattern=r'give periods or')
    refused(f'sentinel_override_{var}', C2, nml(), rf"{var} = -1\.797.*out of range",
            args=['in.nml', f'run.{var}=-1.7976931348623157e308'])
refused('sentinel_sweep_elements', C2, nml() + '&sweep elements=3,-2147483647 min_time=0 /\n',
        r"elements\(2\) = -2147483647 is out of range")
refused('sentinel_sweep_modes', C2, nml() + '&sweep modes=1,-2147483647 min_time=0 /\n',
        r"modes\(2\) = -2147483647 is out of range")
refused('sentinel_sweep_dt', C2, nml() + '&sweep dt_fractions=0.1,-1.7976931348623157e308 min_time=0 /\n',
        r"dt_fractions\(2\) = -0?\.?1\.?797.*out of range")
refused('sentinel_margin_cells', C2, nml(discretisation='elements=4, margin_cells=-2147483647'),
        r"margin_cells = -2147483647 is out of range")
add('end_time_given_replaces_periods', C2, 0, r"end_time=", input=nml(run='end_time=0.001'), exists=['o.h5'],
    not_pattern=r'periods=')
refused('periods_and_end_time', C2, nml(run='periods=1, end_time=0.001'), r"either periods or end_time")
refused('logical_as_number', C2, nml(output="file='o.h5', history=1"), r"'history'.*not a logical")
refused('logical_word', C2, nml(output="file='o.h5', history=yes"), r"'history'.*not a logical")
refused('int_lone_dash', C2, nml(discretisation='elements=-'), r"'elements'.*not a whole number")
refused('int_lone_plus', C2, nml(discretisation='elements=+'), r"'elements'.*not a whole number")

# ---------------------------------------------------------------- 3: messages in the program's words
C3 = '3 messages'
INTS = {'elements': 'discretisation', 'particles_per_element': 'discretisation', 'mode': 'scene',
        'margin_cells': 'discretisation'}
for var, g in INTS.items():
    for tag, value in {'big': '2147483648', 'huge20': '99999999999999999999', 'neg_big': '-2147483649',
                       'huge40': '9' * 40}.items():
        refused(f'int_overflow_{var}_{tag}', C3, nml(**{g: f'{var}={value}'}),
                rf"'{var}'.*beyond the integers of this program \(at most 2147483647\)")
    for tag, value in {'real': '1.5', 'exponent': '1e3', 'text': "'four'", 'logical': '.true.', 'word': 'four'}.items():
        refused(f'int_type_{var}_{tag}', C3, nml(**{g: f'{var}={value}'}), rf"'{var}'.*(whole number|text, not)")
    refused(f'int_override_overflow_{var}', C3, nml(), rf"{var}.*at most 2147483647",
            args=['in.nml', f'{g}.{var}=2147483648'])
for var, g in REALS.items():
    refused(f'real_type_text_{var}', C3, nml(**{g: f"{var}='3.0'"}), rf"'{var}'.*is text, not a real")
    refused(f'real_type_logical_{var}', C3, nml(**{g: f"{var}=.true."}), rf"'{var}'.*not a real number")
    refused(f'real_overflow_{var}', C3, nml(**{g: f"{var}=1e999"}), rf"{var}")
    refused(f'real_nan_{var}', C3, nml(**{g: f"{var}=NaN"}), rf"{var} = NaN is out of range; allowed: (any )?finite")
refused('snapshots_65', C3, nml(output="file='o.h5', snapshot_times=65*0.0"),
        r"'snapshot_times' has 65 values; allowed: up to 64 values")
refused('snapshots_1000', C3, nml(output="file='o.h5', snapshot_times=1000*0.0"), r"has 1000 values; allowed: up to 64")
refused('snapshots_repeat_huge', C3, nml(output="file='o.h5', snapshot_times=99999999999*0.0"),
        r"bad repeat count '99999999999' for 'snapshot_times'")
refused('snapshots_repeat_zero', C3, nml(output="file='o.h5', snapshot_times=0*0.0"), r"bad repeat count '0'")
refused('snapshots_index', C3, nml(output="file='o.h5', snapshot_times(65)=0.0"),
        r"'snapshot_times\(\.\.\.\)': indexed assignment is not supported")
refused('snapshots_index_1', C3, nml(output="file='o.h5', snapshot_times(1)=0.0"), r"indexed assignment")
# sweep lists have no fixed limit any more (the 256 of the issue): 257 values are read, not cut
add('sweep_257_values', C3, 0, r"sweep of 257 cases", input=nml() + f"&sweep elements={','.join(['3'] * 257)} min_time=0 /\n")
add('sweep_repeat_257', C3, 0, r"sweep of 257 cases", input=nml() + "&sweep elements=257*3 min_time=0 /\n")
# large inputs are read in linear time and problems listed up to 100 (each case within its budget of CPU seconds)
refused('snapshots_100000', C3, nml(output="file='o.h5', snapshot_times=" + ','.join(['0.0'] * 100000)),
        r"has 100000 values; allowed: up to 64", cpu_seconds=10)
refused('snapshots_repeat_100000', C3, nml(output="file='o.h5', snapshot_times=100000*0.0"), r"has 100000 values",
        cpu_seconds=10)
refused('unknown_names_20000', C3, '&discretisation ' + ', '.join(f'x{i}=1' for i in range(20000)) + ' /\n',
        r"unknown variable 'x0'.*first 100 are listed", cpu_seconds=10)
refused('groups_20000', C3, '&run periods=1 /\n' * 20000, r"group &run is given twice.*first 100 are listed",
        cpu_seconds=10)
refused('junk_lines_100000', C1, 'junk line\n' * 100000, r"in\.nml:1: text outside.*first 100 are listed", cpu_seconds=10)
add('comments_200000_lines', C1, 0, r"wrote /\S*/o\.h5", input='! c\n' * 200000 + nml(), cpu_seconds=10)
add('blanks_20MB', C1, 0, r"wrote /\S*/o\.h5", input=' ' * 20_000_000 + nml(), cpu_seconds=20)
add('sweep_3000_values', C3, 0, r"sweep of 3000 cases", input=nml() + f"&sweep elements={','.join(['3'] * 3000)} "
    "min_time=0 /\n", cpu_seconds=30)
refused('sweep_repeat_huge', C3, nml() + "&sweep elements=99999999999*3 min_time=0 /\n", r"bad repeat count")
for k in [1, 10, 40]:
    line = ', '.join(['elements=4', 'particles_per_element=1', 'dt_fraction=0.1', "scheme='usl'"][:4] *
                     1) + ', x' * 0
    far = ' ' * (k * 100)
    refused(f'misspelled_far_{k}', C3, nml(discretisation=f"elements=4, {far}particles_per_element=1, {far}"
                                                          f"dt_fraction=0.1, {far}shceme='usl'"),
            r"unknown variable 'shceme'; did you mean 'scheme'\? allowed names: scheme")
    refused(f'misspelled_after_list_{k}', C3, nml(output=f"file='o.h5', snapshot_times=0.0, 0.001,{' ' * k}"
                                                         "histroy=.false."), r"unknown variable 'histroy'")
refused('misspelled_sweep_after_list', C3, nml() + "&sweep elements=3,4, shemes='usl' min_time=0 /\n",
        r"shemes")
refused('variable_of_other_group', C3, nml(scene='elements=4'), r"unknown variable 'elements'")
refused('variable_of_other_kind', C3, nml(scene='gravity=3.0'), r"'gravity' is not used by kind = 'vibrating_bar'")
refused('twice_given', C3, nml(discretisation='elements=4, elements=5'), r"'elements' is given twice")
refused('no_value', C3, nml(discretisation='elements='), r"'elements' has no value")
refused('two_values', C3, nml(discretisation='elements=4, 5'), r"'elements' takes one value, 2 given")
refused('unclosed_quote', C3, nml(discretisation="scheme='usl"), r"text for 'scheme' runs past the end of its line")
refused('override_line_break', C3, nml(), r"text for 'file' runs past the end of its line",
        args=['in.nml', 'output.file=a\nb.h5'])
refused('margin_cells_huge', C3, nml(discretisation='elements=4, margin_cells=2000000000'),
        r"margin_cells = 2000000000.*(allowed: elements \+ margin_cells|memory available)", cpu_seconds=10)
refused('margin_cells_big_memory', C3, nml(discretisation='elements=4, margin_cells=1000000000'),
        r"margin_cells = 1000000000.*memory available", cpu_seconds=10)
add('margin_cells_given_runs', C3, 0, r"wrote /\S*/o\.h5", input=nml(discretisation='elements=4, margin_cells=10'))
# a value refused through a derived quantity names the variable the user typed
for mode in ['1073741823', '100000000', '2000000']:
    refused(f'huge_mode_{mode}', C3, nml(scene=f'mode={mode}'), rf"mode = {mode}.*allowed: mode <=",
            not_pattern=r'^mpm1d: invalid input:\nrun: end time')
# with end_time the run is possible but meaningless: it runs, warned with the elements per wavelength
add('huge_mode_end_time', C3, 0, r"mode 1073741823 has .* elements per wavelength",
    input=nml(scene='mode=1073741823', run='end_time=0.001'))
for value in ['1e-310', '4.9e-324', '2e-308', '1e-320']:
    refused(f'subnormal_length_{value}', C3, nml(scene=f'length={value}'), rf"length = {float(value)!r}.*allowed",
            not_pattern=r'youngs_modulus/density|end time 0')
refused('subnormal_youngs', C3, nml(scene='youngs_modulus=1e-315'), r"youngs_modulus = 1e-315.*subnormal.*allowed")
refused('subnormal_density', C3, nml(scene='density=1e-315'), r"density = 1e-315.*allowed")
refused('tiny_periods', C3, nml(run='periods=1e-300'), r"periods = 1e-300.*allowed")
refused('tiny_end_time', C3, nml(run='end_time=1e-300'), r"end_time = 1e-300.*allowed")
refused('too_many_steps', C3, nml(discretisation='elements=4, dt_fraction=1e-12', run='periods=1e6'),
        r"periods.*too many|steps.*allowed")
refused('wave_speed_overflow', C3, nml(scene='youngs_modulus=1e300, density=1e-300'),
        r"youngs_modulus.*density.*allowed")

# ---------------------------------------------------------------- 4: paths and the command line
C4 = '4 paths'
refused('path_1025_override', C4, nml(), r"override.*too long|longer than 1024",
        args=['in.nml', 'output.file=' + 'a' * 1030 + '.h5'])
refused('path_long_in_folder', C4, nml(output="file='" + 'd/' * 520 + "o.h5'"), r"longer than 1024 characters")
add('name_255_chars', C4, 0, r"wrote", input=nml(output=f"file='{'n' * 252}.h5'"), exists=['n' * 252 + '.h5'])
add('name_250_chars', C4, 0, r"wrote", input=nml(output=f"file='{'m' * 247}.h5'"), exists=['m' * 247 + '.h5'])
add('name_255_sweep', C4, 0, r"wrote", input=nml(output=f"file='{'s' * 252}.h5'") + '&sweep elements=3,4 min_time=0 /\n',
    exists=['s' * 252 + '.h5'])
refused('name_256_chars', C4, nml(output=f"file='{'n' * 253}.h5'"), r"file.*(too long|255)")
refused('fifo_output', C4, nml(output="file='fifo.h5'"), r"not a regular file", setup='mkfifo fifo.h5', absent=[])
# devices through a link in the case's folder: with the guard broken, a run as root replaces the link,
# never the device itself (a first version named /dev/zero and replaced it on a broken build)
refused('dev_null_output', C4, nml(output="file='null.h5'"), r"not a regular file", setup='ln -s /dev/null null.h5',
        absent=[])
refused('dev_full_output', C4, nml(output="file='full.h5'"), r"not a regular file", setup='ln -s /dev/full full.h5',
        absent=[])
refused('folder_output', C4, nml(output="file='sub'"), r"is an existing folder", setup='mkdir sub')
refused('folder_slash_output', C4, nml(output="file='sub/'"), r"names a folder")
refused('missing_folder_output', C4, nml(output="file='nowhere/o.h5'"), r"folder 'nowhere' does not exist")
refused('input_as_output', C4, nml(output="file='in.nml'"), r"is the input file")
refused('input_as_output_spelled', C4, nml(output="file='./in.nml'"), r"is the input file")
refused('empty_file_name', C4, nml(output="file=''"), r"file is empty")
add('fifo_input_read_once', C4, 0, r"wrote /\S*/o\.h5", shell='"$MPM1D" <(printf "%s" "$TEXT")',
    env={'TEXT': nml()}, exists=['o.h5'], cpu_seconds=20)
add('fifo_input_named', C4, 0, r"wrote /\S*/o\.h5", shell='mkfifo in.fifo; (printf "%s" "$TEXT" > in.fifo &) ; '
    '"$MPM1D" in.fifo', env={'TEXT': nml()}, exists=['o.h5'], cpu_seconds=20)
add('fifo_input_sweep', C4, 0, r"wrote /\S*/o\.h5", shell='"$MPM1D" <(printf "%s" "$TEXT")',
    env={'TEXT': nml() + '&sweep elements=3,4 min_time=0 /\n'}, exists=['o.h5'], cpu_seconds=20)
add('fifo_input_empty', C4, 2, r"no namelist group", shell='"$MPM1D" <(true)', cpu_seconds=20, absent=['o.h5'])
add('stdin_input', C4, 0, r"wrote /\S*/o\.h5", args=['-'], stdin=nml(), exists=['o.h5'])
add('options_before_input', C4, 0, r"^$", args=['--quiet', 'in.nml'], input=nml(), exists=['o.h5'])
add('options_around_overrides', C4, 0, r"^$", args=['-q', 'discretisation.elements=3', 'in.nml'], input=nml(),
    exists=['o.h5'])
add('threads_equals_sweep', C4, 0, r"wrote /\S*/o\.h5", args=['--threads=2', 'in.nml'],
    input=nml() + '&sweep elements=3,4 min_time=0 /\n', exists=['o.h5'])
add('threads_space_sweep', C4, 0, r"wrote /\S*/o\.h5", args=['in.nml', '--threads', '1'],
    input=nml() + '&sweep elements=3,4 min_time=0 /\n', exists=['o.h5'])
refused('threads_single_run', C4, nml(), r"--shard and --threads are for a sweep", args=['--threads=2', 'in.nml'])
refused('threads_empty', C4, nml(), r"--threads '' is not a whole number", args=['in.nml', '--threads='])
refused('threads_word', C4, nml(), r"--threads 'two' is not a whole number", args=['in.nml', '--threads=two'])
refused('threads_negative', C4, nml(), r"--threads.*(whole number|out of range)", args=['in.nml', '--threads=-1'])
refused('threads_missing_value', C4, nml(), r"'--threads' needs a value", args=['in.nml', '--threads'])
refused('threads_overflow', C4, nml() + '&sweep elements=3,4 min_time=0 /\n', r"--threads.*(whole number|range)",
        args=['in.nml', '--threads=99999999999'])
refused('shard_malformed', C4, nml() + '&sweep elements=3,4 min_time=0 /\n', r"--shard 1-2 is malformed",
        args=['in.nml', '--shard=1-2'])
refused('shard_zero', C4, nml() + '&sweep elements=3,4 min_time=0 /\n', r"--shard 0/2 is out of range",
        args=['in.nml', '--shard=0/2'])
refused('shard_past', C4, nml() + '&sweep elements=3,4 min_time=0 /\n', r"--shard 3/2 is out of range",
        args=['in.nml', '--shard=3/2'])
refused('empty_argument_first', C4, nml(), r"empty argument", args=['', 'in.nml'])
refused('empty_argument_after', C4, nml(), r"empty argument", args=['in.nml', ''])
refused('empty_argument_alone', C4, None, r"empty argument", args=[''])
refused('unknown_option', C4, nml(), r"unknown option '--fast'", args=['in.nml', '--fast'])
refused('unknown_short_option', C4, nml(), r"unknown option '-x'", args=['-x', 'in.nml'])
refused('two_inputs', C4, nml(), r"too many arguments", args=['in.nml', 'in.nml'])
refused('missing_input', C4, None, r"cannot open input file 'nope\.nml' \(looked for /\S*/nope\.nml, relative to the "
        r"folder mpm1d runs in\): No such file or directory$", args=['nope.nml'])
refused('folder_input', C4, None, r"input file 'sub' is a folder", args=['sub'], setup='mkdir sub')
refused('dev_null_input', C4, None, r"/dev/null.*(empty|no namelist group)", args=['/dev/null'])
refused('override_not_override', C4, nml(), r"too many arguments", args=['in.nml', 'elements=4'])
refused('override_unknown_group', C4, nml(), r"unknown namelist group 'discretization'",
        args=['in.nml', 'discretization.elements=4'])
refused('override_bad_value', C4, nml(), r"'elements'.*('x' is text, not an integer|whole number)", args=['in.nml', 'discretisation.elements=x'])
# the environment a sweep's threads = 0 follows (libgomp's own warning may come first: env_warning)
for v in ['0', '-1', 'abc', '100000', '40000', '99999999999', '4097', '1,0', '2.5']:
    for kind, extra in [('single', ''), ('sweep', '&sweep elements=3,4 min_time=0 /\n')]:
        refused(f'omp_num_threads_{kind}_{v}', C4, nml() + extra, r"OMP_NUM_THREADS = '.*' is not a thread count; "
                r"allowed: whole numbers 1 to 4096", env={'OMP_NUM_THREADS': v}, env_warning=True)
for v in ['1', '2', '4,2', ' 2 ']:
    add(f'omp_num_threads_ok_{v.replace(" ", "_").replace(",", "_")}', C4, 0, r"wrote /\S*/o\.h5", input=nml() + '&sweep elements=3,4 min_time=0 /\n',
        env={'OMP_NUM_THREADS': v}, exists=['o.h5'])
SHARDS = nml() + '&sweep elements=3,4 min_time=0 /\n'
MAKE_SHARDS = ('"$MPM1D" in.nml --shard=1/2 -q && "$MPM1D" in.nml --shard=2/2 -q && ')
add('merge_output_is_shard', C4, 2, r"is one of the shard files", input=SHARDS,
    shell=MAKE_SHARDS + 'cp o_shard001of002.h5 keep.h5; "$MPM1D" merge o_shard001of002.h5 o_shard001of002.h5 '
    'o_shard002of002.h5; rc=$?; cmp -s keep.h5 o_shard001of002.h5 || exit 9; exit $rc')
add('merge_output_is_shard_spelled', C4, 2, r"is one of the shard files", input=SHARDS,
    shell=MAKE_SHARDS + '"$MPM1D" merge ./o_shard002of002.h5 o_shard001of002.h5 o_shard002of002.h5')
add('merge_output_is_shard_link', C4, 2, r"is one of the shard files", input=SHARDS,
    shell=MAKE_SHARDS + 'ln -s o_shard001of002.h5 l.h5; "$MPM1D" merge l.h5 o_shard001of002.h5 o_shard002of002.h5')
add('merge_ok', C4, 0, r"wrote /\S*/m\.h5 from 2 shard files", input=SHARDS,
    shell=MAKE_SHARDS + '"$MPM1D" merge m.h5 o_shard001of002.h5 o_shard002of002.h5', exists=['m.h5'])
add('merge_output_folder', C4, 3, r"m", input=SHARDS, setup='mkdir m.h5',
    shell=MAKE_SHARDS + '"$MPM1D" merge m.h5 o_shard001of002.h5 o_shard002of002.h5')
add('merge_missing_shard', C4, 2, r"nope\.h5", input=SHARDS, shell='"$MPM1D" merge m.h5 nope.h5', absent=['m.h5'])
add('merge_no_args', C4, 2, r"usage: mpm1d merge", args=['merge'])
add('merge_empty_output', C4, 2, r"merge: argument 2 is an empty argument", args=['merge', '', 'a.h5'])
add('merge_empty_shard', C4, 2, r"merge: argument 3 is an empty argument", args=['merge', 'm.h5', ''], absent=['m.h5'])
for first in ['--help', '-h', '--version', '-V', '--list-parameters']:
    add(f'{first.strip("-")}_with_extra', C4, 2, rf"'{first}' takes no other arguments \(given: 'in.nml'\)",
        args=[first, 'in.nml'], input=nml(), absent=['o.h5'])
    add(f'{first.strip("-")}_alone', C4, 0, r"mpm1d|group", args=[first])
add('merge_not_hdf5', C4, 2, r"in\.nml", input=SHARDS, args=['merge', 'm.h5', 'in.nml'], absent=['m.h5'])

# ---------------------------------------------------------------- 5: scale
C5 = '5 scale'
# The bar is dimensionless in L/c, v0/c, mode and the discretisation: scaling lengths by s keeps every
# dimensionless number (a: E, rho, v0 kept, times scale with s; b: E by s^2 and v0 by s, times kept;
# c: rho by 1/s^2 and v0 by s). Each ladder rung must give the reference's relative error, or be refused.
BASE = dict(length=25.0, youngs_modulus=200e9, density=7800.0, velocity_amplitude=0.1)
SCALE_DISC = 'elements=8'
SCALE_RUN = 'periods=0.5'


def scaled(length, youngs_modulus, density, velocity_amplitude, mode=1):
    return nml(scene=f'length={length!r}, youngs_modulus={youngs_modulus!r}, density={density!r}, '
                     f'velocity_amplitude={velocity_amplitude!r}, mode={mode}',
               discretisation=SCALE_DISC, run=SCALE_RUN)


add('scale_reference', C5, 0, r"wrote /\S*/o\.h5", input=scaled(**BASE), ref=True)
add('scale_reference_mode3', C5, 0, r"wrote /\S*/o\.h5", input=scaled(**BASE, mode=3) .replace('elements=8', 'elements=24'),
    ref=True)
for e in range(-200, 201, 20):
    s = 10.0**e
    add(f'scale_a_1e{e}', C5, 0, r"wrote /\S*/o\.h5", input=scaled(25.0*s, 200e9, 7800.0, 0.1), rel_error='@scale_reference')
    add(f'scale_mode3_1e{e}', C5, 0, r"wrote /\S*/o\.h5",
        input=scaled(25.0*s, 200e9, 7800.0, 0.1, mode=3).replace('elements=8', 'elements=24'),
        rel_error='@scale_reference_mode3')
for e in range(-100, 101, 20):
    s = 10.0**e
    add(f'scale_b_1e{e}', C5, 0, r"wrote /\S*/o\.h5", input=scaled(25.0*s, 200e9*s*s, 7800.0, 0.1*s),
        rel_error='@scale_reference')
    add(f'scale_c_1e{e}', C5, 0, r"wrote /\S*/o\.h5", input=scaled(25.0*s, 200e9, 7800.0/(s*s), 0.1*s),
        rel_error='@scale_reference')
# the column (dimensionless in g L/c^2) and the manufactured solution (in A/L) scale as the bar does
add('scale_column_reference', C5, 0, r"wrote /\S*/o\.h5", ref=True,
    input=nml(scene="kind='column', length=25.0, gravity=9.81", discretisation=SCALE_DISC, run=SCALE_RUN))
add('scale_manufactured_reference', C5, 0, r"wrote /\S*/o\.h5", ref=True,
    input=nml(scene="kind='manufactured', length=25.0, amplitude=0.025", discretisation=SCALE_DISC, run=SCALE_RUN))
# their formulas are not written in scaled form: each rung gives the reference's error or is refused (exit 2)
# naming what the user typed; nothing non-finite with exit 0 either way
for e in range(-200, 201, 40):
    s = 10.0**e
    add(f'scale_column_1e{e}', C5, [0, 2], r"wrote /\S*/o\.h5|length = .*gravity = .*allowed", rel_error='@scale_column_reference',
        input=nml(scene=f"kind='column', length={25.0*s!r}, gravity={9.81/s!r}", discretisation=SCALE_DISC,
                  run=SCALE_RUN))
    add(f'scale_manufactured_1e{e}', C5, [0, 2], r"wrote /\S*/o\.h5|length = .*amplitude = .*allowed",
        rel_error='@scale_manufactured_reference',
        input=nml(scene=f"kind='manufactured', length={25.0*s!r}, amplitude={0.025*s!r}", discretisation=SCALE_DISC,
                  run=SCALE_RUN))
refused('scale_column_strain_refused', C5, nml(scene="kind='column', length=1e200"), r"gravity = 9\.81.*allowed")
refused('scale_column_sag_refused', C5, nml(scene="kind='column', length=1e-200"), r"length = 1e-200 m, gravity = 9\.81.*sag.*allowed")
refused("scale_bar_displacement_refused", C5, nml(scene="length=1e-305"), r"velocity_amplitude = 0\.1.*allowed")
refused('scale_v0_moves_too_far', C5, nml(scene="velocity_amplitude=1e12"),
        r"velocity_amplitude = 1e12 m/s moves the free end by about 1e9 cells.*allowed")
add('scale_v0_equal_c_runs', C5, [0, 1], r"wrote /\S*/o\.h5|guard", input=nml(scene="velocity_amplitude=5063.696835418333"))
# beyond what doubles hold: refused, naming what the user typed
for e in [200, 300]:
    s = 10.0**e
    refused(f'scale_b_1e{e}_refused', C5, scaled(25.0*s, min(200e9*s*s, 1e308), 7800.0, 0.1*s),
            r"(length|youngs_modulus|velocity_amplitude|density).*allowed")
refused('scale_energy_overflow', C5, scaled(1e200, 1e300, 1e200, 1e40), r"(density|velocity_amplitude|length).*allowed")
refused('scale_stress_unrepresentable', C5, scaled(25.0, 1e308, 1e-308, 0.1), r"(youngs_modulus|density).*allowed")
# Issue 16, defect 10: E = 1e308 (with rho scaled to keep c) runs; only a sum overflowed before
for rho in ['7800.0', '3.9e300', '1e290']:
    factor = float(rho)/7800.0
    add(f'i16_10_youngs_1e308_rho_{rho}', 'i16.10', 0, r"wrote /\S*/o\.h5",
        input=scaled(25.0, 200e9*factor if factor > 1 else 1e308, float(rho), 0.1 if factor > 1 else 0.1),
        **({'rel_error': '@scale_reference'} if factor > 1 else {}))
add('i16_10_youngs_1e308_default_rho', 'i16.10', 0, r"wrote /\S*/o\.h5",
    input=nml(scene='youngs_modulus=1e308'), not_pattern=r'non_finite')
add('i16_10_youngs_1e308_usf', 'i16.10', 0, r"wrote /\S*/o\.h5",
    input=nml(scene='youngs_modulus=1e308', discretisation="elements=4, scheme='usf'"), not_pattern=r'non_finite')
add('i16_10_youngs_1e308_generic', 'i16.10', 0, r"wrote /\S*/o\.h5",
    input=nml(scene='youngs_modulus=1e308', discretisation="elements=4, kernels='generic'"), not_pattern=r'non_finite')
add('i16_10_youngs_1e308_rho_scaled_generic', 'i16.10', 0, r"wrote /\S*/o\.h5",
    input=scaled(25.0, 1e308, 7800.0*(1e308/200e9), 0.1).replace('elements=8', "elements=8, kernels='generic'"),
    rel_error='@scale_reference', rel_tol=1e-6)
add('i16_10_youngs_1e308_sweep', 'i16.10', 0, r"1 case completed|2 cases completed",
    input=nml(scene='youngs_modulus=1e308') + '&sweep elements=3,4 min_time=0 /\n')

# ---------------------------------------------------------------- 6: signals and concurrency
C6 = '6 signals'
SLOW = nml(discretisation='elements=4', run='periods=0.25')
# No timing assumption (issue 24: these failed on a loaded machine): the run pauses before its rename
# until the signal comes (600 s, the runner's hang guard ends a run the signal missed), and the script
# waits for the partial file as long as the run lives.
for sig in ['INT', 'TERM', 'HUP']:
    for n in range(2):
        add(f'signal_{sig}_while_writing_{n}', C6, 0, None, input=SLOW, env={'MPM1D_PAUSE_BEFORE_RENAME': '600'},
            shell='set -m; "$MPM1D" in.nml -q & pid=$!; until ls *.part >/dev/null 2>&1; do '
                  'kill -0 $pid 2>/dev/null || exit 7; sleep 0.05; done; '
                  f'kill -{sig} $pid; wait $pid; rc=$?; [ $rc -ne 0 ] || exit 8; exit 0', absent=['o.h5'])
# a signal just after the partial file is created: removed (once, the clean-up was registered after the
# file was created, and a signal in between left the file behind)
for sig in ['INT', 'TERM']:
    add(f'signal_{sig}_after_creating_part', C6, 0, None, input=SLOW, env={'MPM1D_PAUSE_AFTER_CREATE': '600'},
        shell='set -m; "$MPM1D" in.nml -q & pid=$!; until ls *.part >/dev/null 2>&1; do '
              'kill -0 $pid 2>/dev/null || exit 7; sleep 0.05; done; '
              f'kill -{sig} $pid; wait $pid; rc=$?; [ $rc -ne 0 ] || exit 8; exit 0', absent=['o.h5'])
# the signal once mpm1d runs (its executable, not the shell before exec, which would lose it); the
# run is long (elements=2000, 50 periods): the signal comes before its output whatever the load
add('signal_INT_before_writing', C6, 0, None, input=nml(discretisation='elements=2000', run='periods=50'),
    shell='set -m; "$MPM1D" in.nml -q & pid=$!; exe=$(readlink -f "$MPM1D"); '
          'until [ "$(readlink -f /proc/$pid/exe 2>/dev/null)" = "$exe" ]; do kill -0 $pid 2>/dev/null || exit 7; '
          'sleep 0.01; done; kill -INT $pid; wait $pid; [ $? -eq 130 ] || exit 8; exit 0',
    absent=['o.h5'])
for n in range(3):
    add(f'two_runs_same_output_{n}', C6, 0, None, input=nml(),
        shell='"$MPM1D" in.nml -q & a=$!; "$MPM1D" in.nml -q & b=$!; wait $a || exit 4; wait $b || exit 5; exit 0',
        exists=['o.h5'])
add('two_sweeps_same_output', C6, 0, None, input=SHARDS,
    shell='"$MPM1D" in.nml -q & a=$!; "$MPM1D" in.nml -q & b=$!; wait $a || exit 4; wait $b || exit 5; exit 0',
    exists=['o.h5'])
add('foreign_part_untouched', C6, 0, None, input=nml(), allow_part=True,
    shell='echo keep > o.h5.part; echo keep > o.h5.99999.part; "$MPM1D" in.nml -q || exit 4; '
          'grep -q keep o.h5.part && grep -q keep o.h5.99999.part', exists=['o.h5', 'o.h5.part'])
add('crash_before_rename_nothing_final', C6, 134, None, input=nml(), allow_part=True,
    env={'MPM1D_CRASH_BEFORE_RENAME': '1'}, shell='"$MPM1D" in.nml -q 2>/dev/null', absent=['o.h5'])

# ---------------------------------------------------------------- issue 16, section 3 (the others)
SW = "&sweep elements=3,4 min_time=0 /\n"
add('i16_01_shard_names_digits', 'i16.1', 0, r"shard 1000 of 1000",
    input=nml() + "&sweep elements=" + ','.join(str(3 + k % 5) for k in range(1000)) + " min_time=0 /\n",
    args=['in.nml', '--shard=1000/1000'], exists=['o_shard1000of1000.h5'], absent=['*[*]*'])
add('i16_01_shard_names_3digits', 'i16.1', 0, r"shard 2 of 2", input=SHARDS, args=['in.nml', '--shard=2/2'],
    exists=['o_shard002of002.h5'])
refused('i16_02_more_shards_than_cases', 'i16.2', SHARDS, r"shards", args=['in.nml', '--shard=1/3'],
        absent=['o_shard*'])
refused('i16_02_more_shards_setting', 'i16.2', nml() + "&sweep elements=3,4 min_time=0, shards=5 /\n", r"shards")
for t in ['40000', '100000', '4097']:
    refused(f'i16_04_threads_{t}', 'i16.4', SHARDS, r"--threads.*out of range; allowed: 0 \(all cores\) to 4096",
            args=['in.nml', f'--threads={t}'])
    refused(f'i16_04_sweep_threads_{t}', 'i16.4', nml() + f"&sweep elements=3,4 min_time=0, threads={t} /\n",
            r"threads = " + t + r" is out of range")
refused('i16_05_output_is_input', 'i16.5', nml(output="file='in.nml'"), r"is the input file", exists=['in.nml'])
refused('i16_05_output_device', 'i16.5', nml(output="file='zero.h5'"), r"not a regular file",
        setup='ln -s /dev/zero zero.h5', absent=[])
refused('i16_05_output_is_input_sweep', 'i16.5', nml(output="file='in.nml'") + SW, r"is the input file")
refused('i16_06_output_folder', 'i16.6', nml(output="file='.'"), r"is an existing folder")
refused('i16_06_output_folder_sweep', 'i16.6', nml(output="file='sub'") + SW, r"is an existing folder",
        setup='mkdir sub')
refused('i16_07_unsorted_snapshots', 'i16.7', nml(output="file='o.h5', snapshot_times=0.0001, 0.00005"),
        r"not in increasing order")
add('i16_07_sorted_snapshots', 'i16.7', 0, r"wrote", input=nml(output="file='o.h5', snapshot_times=0.00001, 0.00002"))
for mode in ['1500000000', '2147483647', '1073741824']:
    refused(f'i16_09_mode_{mode}', 'i16.9', nml(scene=f'mode={mode}', run='end_time=0.001'), rf"mode = {mode}")
add('i16_11_tiny_displacement_warned', 'i16.11', 0, r"below 100 times the rounding of positions",
    input=nml(scene='velocity_amplitude=1e-12'))
add('i16_11_stiff_light_warned', 'i16.11', 0, r"below 100 times the rounding",
    input=nml(scene='youngs_modulus=1e15, density=1e-20'))
add('i16_12_unresolved_mode_warned', 'i16.12', 0, r"elements per wavelength",
    input=nml(scene='mode=50', discretisation='elements=20', run='end_time=1e-3'))
add('i16_12_unresolved_mode_sweep', 'i16.12', 0, r"fewer than 2 elements per wavelength",
    input=nml(scene='mode=50', run='end_time=1e-3') + SW)
refused('i16_13_dollar', 'i16.13', '$scene length=3 $end\n', r"text outside")
refused('i16_13_nul', 'i16.13', b"&scene length=3\x00 /\n", r"'length'")
refused('i16_13_elf', 'i16.13', b'\x7fELF' + b'\x00' * 100, r"text outside")
refused('i16_14_overflow_message', 'i16.14', nml(discretisation='elements=99999999999'), r"at most 2147483647")
refused('i16_14_snapshot_limit', 'i16.14', nml(output="file='o.h5', snapshot_times=65*0.0"), r"up to 64 values")
refused('i16_14_gap_no_placeholder', 'i16.14', nml() + "&sweep elements=1,,3, min_time=0 /\n", r"gap",
        not_pattern=r"2147483647")
add('i16_15_merge_unwritable', 'i16.15', 3, r"m\.h5|cannot", input=SHARDS, setup='mkdir m.h5',
    shell=MAKE_SHARDS + '"$MPM1D" merge m.h5/x/y.h5 o_shard001of002.h5 o_shard002of002.h5')
add('i16_16_merge_threads_differ', 'i16.16', 0, r"wrote /\S*/m\.h5", input=SHARDS,
    shell='"$MPM1D" in.nml --shard=1/2 --threads=1 -q && "$MPM1D" in.nml --shard=2/2 --threads=2 -q && '
          '"$MPM1D" merge m.h5 o_shard001of002.h5 o_shard002of002.h5', exists=['m.h5'])
add('i16_17_scheme_case_single', 'i16.17', 0, r"scheme='usl'", input=nml(discretisation="elements=4, scheme='USL'"))
add('i16_17_scheme_case_sweep', 'i16.17', 0, r"wrote", input=nml() + "&sweep schemes='USL','Musl' min_time=0 /\n")
refused('i16_17_scheme_unknown_sweep', 'i16.17', nml() + "&sweep schemes='usl','fast' min_time=0 /\n",
        r"schemes\(2\) = 'fast' is unknown")

# ---------------------------------------------------------------- issue 24: runs that miss what they are for (3),
# messages that point at the fix (4), the input defects of section 6 (block of the 'messages' helper)
I3, I4, I6 = 'i24.3 misses', 'i24.4 messages', 'i24.6 defects'
# two bars of 1 m, c = sqrt(1e9/1000) = 1000 m/s (period 2 L/c = 2 ms), closing at 2 m/s
BARS = "kind='impact', lengths=1.0, 1.0, youngs_moduli=1e9, 1e9, densities=1000, 1000, "
add('impact_ends_before_contact_warned', I3, 0, r"mpm1d: warning: the bars do not meet before the end of the run: "
    r"gap = 0\.01 m closing at 2 m/s first touches at t = 5e-03 s, after the end time 8e-04 s",
    input=nml(scene=BARS + "velocities=1, -1, gap=0.01", run='end_time=0.0008'), exists=['o.h5'])
# periods count from the first contact: 5 ms + 1 period of 2 ms = 7 ms in steps of 0.1 (2.01/4)/1000 s: 140
add('impact_periods_from_contact', I3, 0, r"# usl, 4 elements, .* 140 steps", not_pattern=r"warning",
    input=nml(scene=BARS + "velocities=1, -1, gap=0.01", run='periods=1'), exists=['o.h5'])
add('impact_bars_apart_warned', I3, 0, r"warning: the bars never meet: velocities = -1, 1 m/s",
    input=nml(scene=BARS + "velocities=-1, 1, gap=0.01", run='periods=1'))
add('impact_sweep_misses_warned', I3, 0, r"warning: 1 case of 2: the bars do not meet before the end of the run: "
    r"gap = 0\.01 m", input=nml(scene=BARS + "velocities=1, -1", run='end_time=0.0008') +
    "&sweep gap=0.0, 0.01, min_time=0 /\n", exists=['o.h5'])
refused('flip_fraction_with_flip', I3, nml(discretisation='elements=4, flip_fraction=0.5'),
        r"in\.nml:2: discretisation: flip_fraction = 0\.5 is used only with transfer = 'blend', not with transfer = "
        r"'flip'; allowed: flip_fraction with transfer = 'blend', or no flip_fraction")
refused('flip_fraction_override_apic', I3, nml(discretisation="elements=4, transfer='apic'"),
        r"command line 'discretisation\.flip_fraction=0\.3': .*not with transfer = 'apic'",
        args=['in.nml', 'discretisation.flip_fraction=0.3'])
add('flip_fraction_with_blend_runs', I3, 0, r"flip_fraction=0\.5", input=nml(discretisation="elements=4, "
    "transfer='blend', flip_fraction=0.5"), exists=['o.h5'])
add('flip_fraction_echo_left_out', I3, 0, r"transfer='pic'", not_pattern=r"flip_fraction *=",
    input=nml(discretisation="elements=4, transfer='pic'"))
refused('sweep_flip_fractions_without_blend', I3, nml() + "&sweep transfer='flip','pic', flip_fraction=0.3,0.5, "
        "min_time=0 /\n", r"sweep: flip_fraction \(the list\) is used only with transfer = 'blend', not with the "
        r"sweep's transfer list \('flip', 'pic'\)")
refused('sweep_flip_fractions_beside_flip', I3, nml() + "&sweep transfer='flip','blend', flip_fraction=0.3,0.5, "
        "min_time=0 /\n", r"has 2 values, but the sweep's transfer 'flip' does not use flip_fraction")
add('sweep_flip_fractions_blend_alone', I3, 0, r"sweep of 3 cases", input=nml(discretisation="elements=4, "
    "transfer='blend'") + "&sweep flip_fraction=0.0, 0.5, 1.0, min_time=0 /\n", exists=['o.h5'])
add('sweep_flip_fraction_used_by_blend', I3, 0, r"sweep of 2 cases", input=nml(discretisation="elements=4, "
    "flip_fraction=0.3") + "&sweep transfer='flip','blend', min_time=0 /\n", exists=['o.h5'])
refused('sweep_flip_fraction_no_case_uses', I3, nml(discretisation="elements=4, flip_fraction=0.3") +
        "&sweep transfer='flip','apic', min_time=0 /\n", r"flip_fraction = 0\.3 is used only with transfer = 'blend'")
# the methods of docs/theory.md, The cures: a parameter of one transfer given to another is refused naming both,
# and the combinations a method does not take are refused naming the variables and what is allowed
refused('xpic_order_with_flip', I3, nml(discretisation='elements=4, xpic_order=3'),
        r"in\.nml:2: discretisation: xpic_order = 3 is used only with transfer = 'xpic', not with transfer = 'flip'; "
        r"allowed: xpic_order with transfer = 'xpic', or no xpic_order")
refused('fmpm_order_with_xpic', I3, nml(discretisation="elements=4, transfer='xpic', fmpm_order=2"),
        r"fmpm_order = 2 is used only with transfer = 'fmpm', not with transfer = 'xpic'")
refused('asflip_alpha_override_pic', I3, nml(discretisation="elements=4, transfer='pic'"),
        r"command line 'discretisation\.asflip_alpha=0\.5': .*used only with transfer = 'asflip', not with transfer = "
        r"'pic'", args=['in.nml', 'discretisation.asflip_alpha=0.5'])
refused('xpic_order_zero', I3, nml(discretisation="elements=4, transfer='xpic', xpic_order=0"),
        r"xpic_order = 0 is out of range; allowed: integer with 1 <= xpic_order <= 100")
refused('fmpm_order_101', I3, nml(discretisation="elements=4, transfer='fmpm', fmpm_order=101"),
        r"fmpm_order = 101 is out of range; allowed: integer with 1 <= fmpm_order <= 100")
refused('asflip_alpha_above_one', I3, nml(discretisation="elements=4, transfer='asflip', asflip_alpha=1.5"),
        r"asflip_alpha = 1\.5 is out of range; allowed: finite real with 0 <= asflip_alpha <= 1")
refused('formulation_misspelled', I3, nml(discretisation="elements=4, formulation='totl'"),
        r"formulation = 'totl' is unknown; did you mean 'total'\?")
refused('total_impact', I3, nml(scene=BARS + "velocities=1, -1", discretisation="elements=4, formulation='total'"),
        r"in\.nml:2: discretisation: formulation = 'total' is not used by kind = 'impact' \(the bars' contact needs "
        r"their current configuration.*allowed: formulation = 'updated', or another kind")
refused('total_implicit', I3, nml(discretisation="elements=4, formulation='total', integrator='implicit'"),
        r"'formulation' is not used by integrator = 'implicit'; it belongs to integrator explicit")
refused('cpdi_asflip', I3, nml(discretisation="elements=4, shape='cpdi', transfer='asflip'"),
        r"transfer = 'asflip' is not used with shape = 'cpdi' \(a CPDI particle is its domain's centre")
refused('cpdi_impact', I3, nml(scene=BARS + "velocities=1, -1", discretisation="elements=4, shape='cpdi'"),
        r"shape = 'cpdi' is not used by kind = 'impact'")
refused('xpic_frictionless_impact', I3, nml(scene=BARS + "velocities=1, -1", discretisation="elements=4, "
        "transfer='xpic'"), r"transfer = 'xpic' is not used with contact = 'frictionless'.*allowed: contact = 'none'")
refused('fmpm_implicit', I3, nml(discretisation="elements=4, transfer='fmpm', integrator='implicit'"),
        r"transfer = 'fmpm' is not used by integrator = 'implicit'; allowed: transfer = 'flip', 'pic', 'blend' or "
        r"'apic', or integrator = 'explicit'")
refused('cpdi_quasi_static', I3, nml(scene="kind='column'", discretisation="elements=4, shape='cpdi', "
        "integrator='quasi_static'", run=None), r"shape = 'cpdi' is not used by integrator = 'quasi_static'")
refused('sweep_xpic_orders_beside_flip', I3, nml() + "&sweep transfer='flip','xpic', xpic_order=2,3, min_time=0 /\n",
        r"has 2 values, but the sweep's transfer 'flip' does not use xpic_order")
add('sweep_methods_run', I3, 0, r"sweep of 6 cases", input=nml(discretisation="elements=4, transfer='xpic'") +
    "&sweep xpic_order=1, 2, 4, formulation='updated', 'total', min_time=0 /\n", exists=['o.h5'])
add('methods_echo_their_parameters', I3, 0, r"transfer='fmpm', fmpm_order=3, formulation='total'",
    not_pattern=r"xpic_order *=", input=nml(discretisation="elements=4, transfer='fmpm', fmpm_order=3, "
    "formulation='total', shape='cpdi'"), exists=['o.h5'])

refused('misspelled_group_suggested', I4, nml(discretisation=None) + "&discretization elements=4 /\n",
        r"in\.nml:\d: unknown namelist group &discretization; did you mean &discretisation\? known groups: &scene, "
        r"&material, &discretisation, &run, &output, &guards, &sweep")
refused('misspelled_group_sweep_listed', I4, nml() + "&sweeps elements=3,4 /\n", r"did you mean &sweep\?")
refused('misspelled_variable_suggested', I4, nml(discretisation='elemnts=4'),
        r"unknown variable 'elemnts'; did you mean 'elements'\? allowed names: scheme, elements")
refused('misspelled_keyword_suggested', I4, nml(discretisation="elements=4, scheme='usx'"),
        r"scheme = 'usx' is unknown; did you mean 'usf' or 'usl'\?")
refused('misspelled_kind_suggested', I4, nml(scene="kind='vibrating bar'"), r"did you mean 'vibrating_bar'\?")
refused('variable_in_wrong_group_named', I4, nml(run='elements=40'),
        r"in\.nml:3: group &run: unknown variable 'elements'; it belongs to &discretisation")
refused('override_in_wrong_group_named', I4, nml(), r"command line 'run\.elements=40': group &run: unknown variable "
        r"'elements'; it belongs to &discretisation: discretisation\.elements=40", args=['in.nml', 'run.elements=40'])
refused('override_misspelled_group', I4, nml(), r"unknown namelist group 'discretization'; did you mean "
        r"'discretisation'\?", args=['in.nml', 'discretization.elements=4'])
refused('bare_override_alone', I4, None, r"argument 'elements=40' is neither a file nor an override; an override "
        r"names its group: discretisation\.elements=40", args=['elements=40'])
refused('bare_override_after_input', I4, nml(), r"an override names its group: discretisation\.elements=40",
        args=['in.nml', 'elements=40'])
refused('bare_sweep_list', I4, nml(), r"sweep\.elements=3,4 \(a sweep over these values\)",
        args=['in.nml', 'elements=3,4'])
refused('bare_sweep_setting', I4, nml() + SW, r"sweep\.min_time=0", args=['in.nml', 'min_time=0'])
refused('sweep_variable_not_swept', I4, nml() + "&sweep length=1,2 /\n", r"'length' of &scene is not swept")
refused('unknown_kind_alone', I4, nml(scene="kind='beam', gravity=3.0, gap=0.5, lengths=1.0, 1.0"),
        r"kind = 'beam' is unknown", not_pattern=r"not used by")
refused('unknown_kind_sweep_alone', I4, nml(scene="kind='beam'") + "&sweep gravity=1.0, 2.0, min_time=0 /\n",
        r"kind = 'beam' is unknown", not_pattern=r"not used by")
# the small bar ends at 0.25 periods = L/c = 25/5063.7 s = 4.937e-03 s
refused('snapshot_after_end_readable', I4, nml(output="file='o.h5', snapshot_times=0.001, 0.5"),
        r"in\.nml:4: output: snapshot_times\(2\) = 0\.5 s is after the end of the run at 4\.937e-03 s; allowed: "
        r"times within the run, 0 to 4\.937e-03 s", not_pattern=r"E-0|\d{10}")
refused('snapshots_unsorted_placed', I4, nml(output="file='o.h5', snapshot_times=0.002, 0.001"),
        r"in\.nml:4: output: snapshot_times = 0\.002, 0\.001 are not in increasing order")
refused('manufactured_amplitude_readable', I4, nml(scene="kind='manufactured', length=1.0, amplitude=0.2"),
        r"amplitude = 0\.2 m, length = 1 m give 1\.257; allowed: amplitude < 0\.1592 m", not_pattern=r"\d{8}")
for opt in [['--threads=-1'], ['--threads', '-1']]:
    refused('threads_minus_one' + opt[0][9:], I4, nml() + SW, r"--threads -1 is out of range; allowed: 0 \(all "
            r"cores\) to 4096", args=['in.nml'] + opt)
refused('shard_minus_one', I4, nml() + SW, r"--shard -1/2 is out of range: I = -1 must be >= 1; allowed: I/N, whole "
        r"numbers with 1 <= I <= N", args=['in.nml', '--shard=-1/2'])
refused('shard_zero_count', I4, nml() + SW, r"--shard 1/0 is out of range: N = 0 must be >= 1",
        args=['in.nml', '--shard', '1/0'])
refused('shard_past_count', I4, nml() + SW, r"--shard 3/2 is out of range: I = 3 must be <= N = 2",
        args=['in.nml', '--shard=3/2'])
refused('utf8_bom_named', I4, b'\xef\xbb\xbf' + nml().encode(), r"in\.nml:1: the input starts with a UTF-8 byte-order "
        r"mark \(bytes EF BB BF\)", not_pattern=r"text outside")
refused('utf16_le_bom_named', I4, nml().encode('utf-16-le').join([b'\xff\xfe', b'']),
        r"in\.nml:1: the input is UTF-16 text \(it starts with the byte-order mark FF FE\)")
refused('utf16_be_bom_named', I4, nml().encode('utf-16-be').join([b'\xfe\xff', b'']),
        r"in\.nml:1: the input is UTF-16 text \(it starts with the byte-order mark FE FF\)")
refused('utf16_le_unmarked_named', I4, nml().encode('utf-16-le'), r"in\.nml:1: the input looks like UTF-16 text",
        not_pattern=r"text outside")
refused('nul_named', I4, nml(discretisation='elements=4\0'), r"bad value for 'elements': '4\\0' holds a NUL byte "
        r"\(\\0, character code 0\)")
refused('nul_binary_named', I4, b'\0\0\0\0garbage', r"text outside a namelist group: '\\0\\0\\0\\0garbage' \(NUL "
        r"bytes: not a text file\?\)")
# c1 = sqrt(1e300/1000) = 3.162e148 m/s, 1e147 times c2 = sqrt(1e6/1000) = 31.62 m/s
refused('composite_youngs_1e300_named', I4, nml(scene="kind='composite_bar', lengths=1.0, 1.0, youngs_moduli=1e300, "
        "1e6, densities=1000, 1000"), r"in\.nml:1: scene: youngs_moduli\(1\) = 1e300 Pa and densities\(1\) = 1000 "
        r"kg/m\^3 give segment 1 a wave speed of 3\.162e\+148 m/s, 1e\+147 times segment 2's \(31\.62 m/s\)")
# dx = (1 + 1e300 + 1)/4; each bar at least half a cell: gap <= 2 x 1 x 4 - 2 = 6 m
refused('impact_gap_1e300_named', I4, nml(scene=BARS + "velocities=1, -1, gap=1e300"),
        r"in\.nml:1: scene: gap = 1e300 m with lengths = 1, 1 m on elements = 4 .*allowed: .*gap <= 6 m at elements "
        r"= 4", not_pattern=r"periods")
add('help_kind_lists_every_scene', I4, 0, r"kind = 'vibrating_bar': the problem \(docs/user-guide\.md, Scenes\): "
    r"'vibrating_bar' .*; 'column' .*; 'manufactured' .*; 'composite_bar' .*; 'impact' two bars colliding",
    args=['--help'], not_pattern=r"README")
add('help_periods_composite', I4, 0, r"periods = 2: run length in periods of the scene \(vibrating_bar: .*composite_bar: "
    r"sum L_i/c_i.*impact: 2 max L/c, from their first contact[;)]", args=['--help'])

refused('nul_in_output_file_name', I6, nml(output="file='out\0.h5'"),
        r"in\.nml:4: output: bad value for 'file': 'out\\0\.h5' holds a NUL byte", absent=['out', 'out*', 'o.h5'])
COMPOSITE = "kind='composite_bar', lengths=1.0, 1.0, youngs_moduli=16e6, 1e6, densities=1000, 1000, "
# T = 0.25 (1/126.5 + 1/31.62) s = 9.882e-3 s; 4 v T in cells of 2/4 m must stay below 1e8: v <= 1.265e9 m/s
for v in ['1e10', '1e100', '1e300']:
    refused(f'composite_drive_velocity_{v}', I6, nml(scene=COMPOSITE + f"drive_velocity={v}"),
            rf"in\.nml:1: scene: drive_velocity = {v} m/s moves the bar's free end by up to 4 v T = .*allowed: at "
            r"most 1e8 cells, drive_velocity <= 1\.265e\+09 m/s")
for v in ['1e4', '1e6']:
    add(f'composite_drive_velocity_{v}_guard', I6, 1, r"guard volume_ratio_not_positive",
        input=nml(scene=COMPOSITE + f"drive_velocity={v}"))
# T = 0.25 x 2 L/c = 5e-4 s; 1.5 |v| T in cells of 2/4 m must stay below 1e8: |v| <= 6.667e10 m/s
refused('impact_velocities_1e12', I6, nml(scene=BARS + "velocities=1e12, -1"),
        r"scene: velocities = 1e12, -1 m/s move the bars' outer ends by up to .*allowed: at most 1e8 cells, "
        r"\|velocities\| <= 6\.667e\+10 m/s")
# every real scene variable at far values, each scene: refused by name, stopped by a guard or run; never a crash
FAR = {'vibrating_bar': dict(kind="'vibrating_bar'"), 'column': dict(kind="'column'"),
       'manufactured': dict(kind="'manufactured'"),
       'composite_bar': dict(kind="'composite_bar'", lengths='1.0, 1.0', youngs_moduli='16e6, 1e6',
                             densities='1000, 1000', drive_velocity='1.0'),
       'impact': dict(kind="'impact'", lengths='1.0, 1.0', youngs_moduli='1e9, 1e9', densities='1000, 1000',
                      velocities='1.0, -1.0', gap='0.01')}
FAR_VARIABLES = {'vibrating_bar': ['length', 'youngs_modulus', 'density', 'velocity_amplitude'],
                 'column': ['length', 'youngs_modulus', 'density', 'gravity'],
                 'manufactured': ['length', 'youngs_modulus', 'density', 'amplitude'],
                 'composite_bar': ['lengths', 'youngs_moduli', 'densities', 'drive_velocity'],
                 'impact': ['lengths', 'youngs_moduli', 'densities', 'velocities', 'gap']}
for kind, variables in FAR_VARIABLES.items():
    for var in variables:
        for value in ['1e10', '1e100', '1e300']:
            values = dict(FAR[kind])
            # a list: its first value far (the impact's second bar keeps its impedance only by chance: refused then)
            values[var] = value + values[var][values[var].index(','):] if ',' in values.get(var, '') else value
            add(f'far_{kind}_{var}_{value}', I6, [0, 1, 2], None,
                input=nml(scene=', '.join(f'{k}={v}' for k, v in values.items())), cpu_seconds=60)


# ---------------------------------------------------------------- issue 24 (helper "trust"): stopped
# cases, interrupted and resumed sweeps, dry runs, absolute paths, merge into a pipe
C24 = 'i24 trust'
#: 12 cases (4 of them stopped by the energy guard), histories, one thread
SWEEP12 = nml(run="periods=2") + "&sweep elements=3, 4, 5, dt_fraction=0.1, 0.5, 2.5, 0.3, min_time=0, threads=1, histories=.true. /\n"
# a sweep's log (standard error not a terminal) gets progress lines of their own (every 60 s; the test
# hook MPM1D_PROGRESS_LOG_SECONDS=0 asks for one per case), the last one saying every case is done
add('i24_sweep_log_has_progress_lines', C24, 0, r'error pass: 12 / 12 cases, \S+ s elapsed', input=SWEEP12,
    env={'MPM1D_PROGRESS_LOG_SECONDS': '0'})
add('i24_short_sweep_log_has_no_progress_line', C24, 0, r'wrote /\S*/o\.h5', input=SWEEP12,
    not_pattern=r'error pass: \d+ / 12')
#: how many cases of o.h5 have status not_run
NOT_RUN = 'h5dump -d /cases/status_name o.h5 | grep -o not_run | wc -l'
#: the sweep pauses (test hook) after N cases, creating mpm1d_paused, until the signal comes: a known point
PAUSED = ('set -m; "$MPM1D" in.nml -q output.file=u.h5 || exit 3; '
          'MPM1D_PAUSE_AFTER_CASES={after} "$MPM1D" in.nml > log.txt 2> err.txt & pid=$!; '
          'until [ -e mpm1d_paused ]; do kill -0 $pid 2>/dev/null || exit 4; sleep 0.02; done; '
          # the redirected log of the sweep under way has its header (standard output flushed)
          'grep -q "sweep of 12 cases" log.txt || exit 6; '
          'kill -{sig} $pid; wait $pid; rc=$?; [ $rc = {code} ] || {{ cat err.txt; exit 5; }}; ')
for sig, code in (('INT', 130), ('TERM', 143), ('HUP', 129)):
    add(f'i24_sweep_{sig}_keeps_work_and_resumes', C24, 0, r'interrupted after 4 of 12 cases; the others have status '
        r'not_run \(no values\) in /\S*/o\.h5; mpm1d in\.nml --resume runs them', input=SWEEP12,
        shell=PAUSED.format(after=4, sig=sig, code=code) +
        f'[ "$({NOT_RUN})" = 8 ] || exit 7; cp o.h5 interrupted.h5; '
        # resumed, the file equals an uninterrupted run's bit for bit: every /cases column, every history
        '"$MPM1D" in.nml --resume -q || exit 8; h5diff -q u.h5 o.h5 /cases /cases || exit 9; '
        'h5diff -q u.h5 o.h5 /histories /histories || exit 10; cat err.txt', exists=['o.h5', 'interrupted.h5'])
# a resumed sweep's report says that its pass times are summed over the attempts, and gives this one's
add('i24_resumed_sweep_times_summed_over_attempts', C24, 0, r'error pass \S+ s on 1 thread \(summed over the '
    r'attempts: this one \S+ s, the earlier ones \S+ s\); no timing pass', input=SWEEP12,
    shell=PAUSED.format(after=4, sig='INT', code=130) + '"$MPM1D" in.nml --resume > resumed.txt || exit 8; '
    'cat resumed.txt', exists=['o.h5'])
#: a Python check of o.h5's /cases: H5 "EXPRESSION" (c: the columns as numpy arrays) must hold
H5 = ('"$PYTHON" -c "import sys, h5py, numpy as np; f = h5py.File(\'o.h5\'); '
      'c = {k: np.asarray(v[()]) for k, v in f[\'cases\'].items()}; sys.exit(0 if (%s) else 1)"')
# interrupted in the timing pass (after the 12 cases of the error pass and 2 timed): every case ran,
# 2 of the 9 completed ones are timed; resumed: all 9 timed, every other column as an uninterrupted run
add('i24_sweep_interrupted_in_timing_pass', C24, 0, r'interrupted after 12 of 12 cases, in the timing pass '
    r'\(2 of 9 completed cases timed; the others\' run_time is NaN\) in /\S*/o\.h5; mpm1d in\.nml --resume times them',
    input=SWEEP12.replace('min_time=0,', 'min_time=0.002,'),
    shell=PAUSED.format(after=14, sig='INT', code=130) +
    f'[ "$({NOT_RUN})" = 0 ] || exit 7; ' +
    H5 % "sum(c['repeats'] > 0) == 2 and np.isnan(c['run_time']).sum() == 10" + ' || exit 8; '
    '"$MPM1D" in.nml --resume -q || exit 9; '
    'for d in $(h5ls o.h5/cases | cut -d" " -f1); do case $d in run_time|repeats|run_time_spread|timing_rounds) '
    'continue;; esac; h5diff -q u.h5 o.h5 /cases/$d /cases/$d || exit 10; done; ' +
    H5 % "all((c['repeats'] > 0) == (c['status'] == 0)) and all(np.isnan(c['run_time']) == (c['status'] != 0))" +
    ' || exit 11; cat err.txt', exists=['o.h5'])
# a shard interrupted and resumed merges with the others into the uninterrupted sweep's table
add('i24_shard_interrupted_resumed_merges', C24, 0, r'wrote /\S*/m\.h5 from 2 shard files', input=SWEEP12,
    shell='set -m; "$MPM1D" in.nml -q output.file=u.h5 || exit 3; "$MPM1D" in.nml -q --shard 1/2 || exit 4; '
          'MPM1D_PAUSE_AFTER_CASES=2 "$MPM1D" in.nml --shard 2/2 > log.txt 2> err.txt & pid=$!; '
          'until [ -e mpm1d_paused ]; do kill -0 $pid 2>/dev/null || exit 5; sleep 0.02; done; '
          'kill -TERM $pid; wait $pid; [ $? = 143 ] || exit 6; '
          'grep -q "interrupted after 2 of 6 cases.*--shard 2/2 --resume" err.txt || exit 7; '
          '"$MPM1D" in.nml --shard 2/2 --resume -q || exit 8; '
          '"$MPM1D" merge m.h5 o_shard001of002.h5 o_shard002of002.h5 || exit 9; '
          'h5diff -q u.h5 m.h5 /cases /cases || exit 10', exists=['m.h5'])
# --resume: another sweep's file is refused by name and left as it was; a missing file too; a
# finished file is left alone; --resume is for sweeps
add('i24_resume_other_sweep_refused', C24, 2, r"resume: 'o\.h5' holds another sweep: its &sweep group differs",
    input=SWEEP12, shell='"$MPM1D" in.nml -q || exit 3; cp o.h5 keep.h5; '
                         '"$MPM1D" in.nml sweep.elements=3,6 --resume; rc=$?; cmp -s o.h5 keep.h5 || exit 9; exit $rc')
add('i24_resume_other_base_refused', C24, 2, r"resume: 'o\.h5' holds another sweep: its configuration",
    input=SWEEP12, shell='"$MPM1D" in.nml -q || exit 3; "$MPM1D" in.nml scene.velocity_amplitude=0.2 --resume')
add('i24_resume_missing_file', C24, 2, r"resume: 'o\.h5' does not exist .*nothing to resume", input=SWEEP12,
    args=['in.nml', '--resume'], absent=['o.h5'])
add('i24_resume_nothing_left', C24, 0, r"nothing to resume: every case of /\S*/o\.h5 ran", input=SWEEP12,
    shell='"$MPM1D" in.nml -q || exit 3; cp -p o.h5 keep.h5; "$MPM1D" in.nml --resume; rc=$?; '
          'cmp -s o.h5 keep.h5 || exit 9; exit $rc')
refused('i24_resume_single_run', C24, nml(), r"--resume is for a sweep", args=['in.nml', '--resume'])
# stopped cases: no value in max_error (NaN; the suite's rule allows NaN only there), the error before
# the stop in its own column; a single stopped run the same in /summary
add('i24_stopped_case_no_value', C24, 0, r"2 cases completed, 2 stopped by a guard", input=nml(run="periods=2") +
    "&sweep elements=3, 4, dt_fraction=0.1, 2.5, min_time=0 /\n",
    shell='"$MPM1D" in.nml || exit 3; ' + H5 % (
        "list(c['status'] != 0) == [False, True, False, True] and all(np.isnan(c['max_error']) == (c['status'] != 0)) "
        "and all(np.isnan(c['relative_error']) == (c['status'] != 0)) and all(np.isnan(c['error_before_stop']) == "
        "(c['status'] == 0)) and all(c['error_before_stop'][c['status'] != 0] > 0) and all(np.isnan(c['run_time'])) "
        "and all(c['repeats'] == 0)") + ' || exit 4')
add('i24_stopped_run_no_value', C24, 1, r"no result \(stopped by a guard\); before the stop: max",
    input=nml(discretisation='elements=4, dt_fraction=2.5', run='periods=2'),
    shell='"$MPM1D" in.nml; rc=$?; h5dump -d /summary/max_error o.h5 | grep -q "(0): nan" || exit 4; '
          'h5dump -d /summary/error_before_stop o.h5 | grep -qE "\(0\): [0-9]" || exit 5; exit $rc')
# a run says the absolute path of what it wrote
add('i24_run_absolute_path', C24, 0, None, input=nml(),
    shell='"$MPM1D" in.nml | grep -qx "wrote $PWD/o.h5"')
add('i24_sweep_absolute_path', C24, 0, None, input=SHARDS,
    shell='"$MPM1D" in.nml | grep -qx "wrote $PWD/o.h5"')
add('i24_merge_absolute_path', C24, 0, None, input=SHARDS,
    shell=MAKE_SHARDS + '"$MPM1D" merge m.h5 o_shard001of002.h5 o_shard002of002.h5 | '
                        'grep -qx "wrote $PWD/m.h5 from 2 shard files"')
# --dry-run: the number of cases and the absolute output path (shards' files when sharded), nothing runs
add('i24_dry_run_sweep', C24, 0, r"cases: 12\noutput: /\S+/o\.h5\n", input=SWEEP12, args=['in.nml', '--dry-run'],
    absent=['o.h5'])
add('i24_dry_run_shards', C24, 0, r"cases: 12\nshards: 5\noutput: /\S+/o\.h5\nshard 1: 3 cases, /\S+/o_shard001of005\.h5\n"
    r"shard 2: 3 cases, .*shard 5: 2 cases, /\S+/o_shard005of005\.h5", input=SWEEP12,
    args=['in.nml', '--dry-run', '--shard', '2/5'], absent=['o*.h5'])
add('i24_dry_run_quoted_name_with_space', C24, 0, r"output: /\S+/x y\.h5", input=nml(output='file="x y.h5"') + SW,
    args=['in.nml', '--dry-run'], absent=['x y.h5'])
add('i24_dry_run_single', C24, 0, r"cases: 1\noutput: /\S+/o\.h5\nsteps: [1-9][0-9]*\n", input=nml(), args=['in.nml', '--dry-run'],
    absent=['o.h5'])
refused('i24_dry_run_more_shards_than_cases', C24, SWEEP12, r"shards = 13 is more than the sweep's 12 cases",
        args=['in.nml', '--dry-run', '--shard=1/13'])
# merge into a named pipe: refused as a single run refuses it, the pipe left as it was
add('i24_merge_into_fifo', C24, 2, r"merge: output file 'm\.h5' is not a regular file", input=SHARDS,
    shell=MAKE_SHARDS + 'mkfifo m.h5; "$MPM1D" merge m.h5 o_shard001of002.h5 o_shard002of002.h5; rc=$?; '
                        '[ -p m.h5 ] || exit 9; exit $rc')
add('i24_single_run_into_fifo', C24, 2, r"not a regular file", input=nml(), setup='mkfifo o.h5',
    shell='"$MPM1D" in.nml; rc=$?; [ -p o.h5 ] || exit 9; exit $rc')

# ---------------------------------------------------------------- 7: runs that survive: a full disk
# A file-size limit (ulimit -f, in KiB) makes every write past it fail (EFBIG) as a full disk does
# (test/cli/test_full_disk.py fills a real tmpfs too): exit 3, a message naming the file and the cause,
# the older file of that name intact, no temporary file (the suite's rule), no crash in the exit handlers.
C7 = '7 survival'
KEEP = 'echo older > {f}; cp {f} older.txt; '
INTACT = 'cmp -s {f} older.txt || exit 9; '
add('full_disk_single_run', C7, 3, r"(?m)^mpm1d: HDF5 output 'o\.h5': cannot .*: file too large",
    input=nml(discretisation='elements=400', run='periods=1'),
    shell=KEEP.format(f='o.h5') + '(ulimit -f 16; "$MPM1D" in.nml -q); rc=$?; ' + INTACT.format(f='o.h5') + 'exit $rc')
add('full_disk_sweep', C7, 3, r"(?m)^mpm1d: HDF5 output 'o\.h5': cannot .*: file too large", input=SWEEP12,
    shell=KEEP.format(f='o.h5') + '(ulimit -f 24; "$MPM1D" in.nml -q); rc=$?; ' + INTACT.format(f='o.h5') + 'exit $rc')
add('full_disk_merge', C7, 3, r"(?m)^mpm1d: HDF5 output 'm\.h5': cannot .*: file too large", input=SWEEP12,
    shell='"$MPM1D" in.nml --shard=1/2 -q && "$MPM1D" in.nml --shard=2/2 -q || exit 4; ' + KEEP.format(f='m.h5') +
          '(ulimit -f 24; "$MPM1D" merge m.h5 o_shard001of002.h5 o_shard002of002.h5); rc=$?; ' +
          INTACT.format(f='m.h5') + 'exit $rc')

# ---------------------------------------------------------------- the laws and integrators under hostile input
# Each to a clear refusal, a guard naming the real cause, or a correct run.
C8 = '8 laws and integrators'
COLUMN_QS = "&scene kind='column' /\n&discretisation integrator='quasi_static' /\n&output file='o.h5' /\n"
IMPACT_NONE = ("&scene kind='impact', lengths=1.0, 1.0, youngs_moduli=200.0e9, 200.0e9, densities=7800.0, 7800.0, "
               "velocities=1.0, -1.0, gap=0.0, contact='none' /\n&run periods=0.25 /\n&output file='o.h5' /\n")
COMPOSITE = ("&scene kind='composite_bar', lengths=1.0, 1.0, youngs_moduli=16.0e6, 1.0e6, densities=1000.0, 1000.0, "
             "drive_velocity=0.01 /\n&output file='o.h5' /\n")
WAVE = "&scene kind='plastic_wave' /\n&material law='elastoplastic' /\n&output file='o.h5' /\n"
# a cap on Newton's solves no longer sizes an array: 2^31 - 1 runs as the default (it allocated 17 GB)
add('i38_max_newton_iterations_huge_runs', C8, 0, None, ref=True, output='o.h5', cpu_seconds=5,
    input=COLUMN_QS.replace("'quasi_static'", "'quasi_static', max_newton_iterations=2147483647"))
add('i38_max_newton_iterations_default', C8, 0, None, input=COLUMN_QS,
    rel_error='@i38_max_newton_iterations_huge_runs', rel_tol=0.0)
# a ghost penalty between -1 (automatic) and 0 was silently the automatic one; beyond 1e6 it only
# conditions the tangent worse (1e15: error 0.9 with status ok)
for g in ('-0.5', '-1e-300'):
    refused(f'i38_ghost_penalty_{g}', C8, COLUMN_QS.replace("'quasi_static'", f"'quasi_static', ghost_penalty={g}"),
            r"ghost_penalty = -[0-9.e-]+; allowed: -1 \(automatic.*or 0 to 1000000")
for shape, g in (('ugimp', '1e15'), ('bspline2', '1e300')):
    refused(f'i38_ghost_penalty_{shape}_{g}', C8, COLUMN_QS.replace(
        "'quasi_static'", f"'quasi_static', shape='{shape}', ghost_penalty={g}"),
        r"ghost_penalty = \S+ is out of range; allowed: finite real with -1 <= ghost_penalty <= 1000000")
# the consistent mass matrix with one particle per element is singular (it ran into NaN): a guard names it;
# two particles per element run
SINGULAR = r"the consistent mass matrix is singular .*allowed: particles_per_element >= 2, or mass = 'lumped'"
for name, text in (('impact_none', IMPACT_NONE), ('composite', COMPOSITE.replace(
        "/\n&output", "/\n&run periods=0.5 /\n&output")), ('plastic_wave', WAVE)):
    consistent = f"&discretisation integrator='implicit', mass='consistent'{', dt_fraction=0.1' if name == 'composite' else ''} /\n"
    add(f'i38_consistent_mass_{name}_one_particle', C8, 1, SINGULAR, input=text + consistent)
    add(f'i38_consistent_mass_{name}_two_particles', C8, 0, None,
        input=text + consistent.replace("'consistent'", "'consistent', particles_per_element=2"))
# the plastic wave at a drive whose energies underflow: refused by name; far below the rounding of positions
# it runs alike (its stress error keeps its digits) and no warning names the bar's velocity_amplitude;
# the one warning says that so slow a drive cannot yield
refused('i38_plastic_wave_drive_1e-200', C8, WAVE.replace("'plastic_wave'", "'plastic_wave', drive_velocity=1e-200"),
        r"drive_velocity = 1e-200 m/s.*the drive's work rho V\^2 L is about 1e-395")
add('i38_plastic_wave_drive_1e-150_runs', C8, 0, None,
    input=WAVE.replace("'plastic_wave'", "'plastic_wave', drive_velocity=1e-150"))
add('i38_plastic_wave_drive_1e-30_no_bar_advice', C8, 0,
    r'mpm1d: warning: the plastic wave cannot yield: drive_velocity = 1e-30 m/s is at or below the yield '
    r'velocity yield_stress/\(density c\) = 6\.33 m/s',
    not_pattern=r'velocity_amplitude|warning: (?!the plastic wave cannot yield)',
    input=WAVE.replace("'plastic_wave'", "'plastic_wave', drive_velocity=1e-30"))
# a run stopped before the drive did work: energy_balance is no value (NaN, the status saying why), not 0/0
add('i38_plastic_wave_stopped_at_first_step', C8, 1, r"guard newton_not_converged tripped at step 1",
    input=WAVE + "&discretisation integrator='implicit', max_newton_iterations=1 /\n",
    shell='"$MPM1D" in.nml -q; rc=$?; ' + H5.replace("f['cases']", "f['summary']") % (
        "c['drive_work'] == 0 and np.isnan(c['energy_balance']) and c['status'] == 7") + ' || exit 9; exit $rc')
# E_t = E H/(E + H) is representable although E H is not: a stiff hardening runs (it tripped non_finite)
for integrator in ('explicit', 'implicit'):
    add(f'i38_hardening_1e300_{integrator}', C8, 0, None,
        input=WAVE.replace("'elastoplastic'", "'elastoplastic', hardening_modulus=1e300").replace(
            "'plastic_wave'", "'plastic_wave', drive_velocity=100") + f"&discretisation integrator='{integrator}' /\n",
        shell='"$MPM1D" in.nml -q || exit 4; ' + H5.replace("f['cases']", "f['summary']") % (
            "c['tangent_modulus'] == 2e11 and c['yields'] == 1"))
# a perfectly plastic column yielding at its fixed end has no equilibrium: refused, naming the cause
for integrator in ('quasi_static', 'explicit'):
    refused(f'i38_perfectly_plastic_column_{integrator}', C8,
            f"&scene kind='column' /\n&material law='elastoplastic', hardening_modulus=0, yield_stress=1e3 /\n"
            f"&discretisation integrator='{integrator}' /\n&output file='o.h5' /\n",
            r"hardening_modulus = 0 \(perfectly plastic\) with yield_stress = 1000 Pa, below the column's weight at "
            r"its fixed end rho g L = 1\.913e\+06 Pa: the column yields and has no equilibrium")
# load_steps beyond the step counter: refused naming load_steps, once (it named periods, twice)
refused('i38_load_steps_huge', C8, COLUMN_QS.replace("'quasi_static'", "'quasi_static', load_steps=2147483647"),
        r"^mpm1d: invalid input:\n[^\n]*load_steps = 2147483647 is out of range; allowed: integer with 1 <= "
        r"load_steps <= 2147483646\n?$", not_pattern='periods')
# SIGKILL: each finished case is in the journal beside the output (o.h5.journal), --resume continues from it
# to the uninterrupted table (test/cli/test_sweep_kill.py kills at 24 random moments and tears journals)
KILLED = ('set -m; "$MPM1D" in.nml -q output.file=u.h5 || exit 3; '
          'MPM1D_PAUSE_AFTER_CASES=4 "$MPM1D" in.nml -q 2> err.txt & pid=$!; '
          'until [ -e mpm1d_paused ]; do kill -0 $pid 2>/dev/null || exit 4; sleep 0.02; done; '
          'kill -KILL $pid; wait $pid; [ $? = 137 ] || exit 5; [ -s o.h5.journal ] || exit 6; [ ! -e o.h5 ] || exit 7; ')
add('sigkill_sweep_resumes_from_journal', C7, 0, r"resumed: 4 of 12 cases ran before \(kept\); 8 to run\n"
    r"from the journal 'o\.h5\.journal': 4 cases, 0 timings", input=SWEEP12,
    shell=KILLED + '"$MPM1D" in.nml --resume || exit 8; h5diff -q u.h5 o.h5 /cases /cases || exit 9; '
          'h5diff -q u.h5 o.h5 /histories /histories || exit 10; [ ! -e o.h5.journal ] || exit 11')
add('torn_journal_record_dropped', C7, 0, r"from the journal 'o\.h5\.journal': 3 cases, 0 timings; a torn last record "
    r"of \d+ bytes dropped", input=SWEEP12,
    shell=KILLED + 'truncate -s -5 o.h5.journal; "$MPM1D" in.nml --resume || exit 8; '
          'h5diff -q u.h5 o.h5 /cases /cases || exit 9; h5diff -q u.h5 o.h5 /histories /histories || exit 10')
add('journal_of_another_sweep_refused', C7, 2, r"resume: the journal 'o\.h5\.journal' holds another sweep: its "
    r"configuration \(/config\) differs", input=SWEEP12,
    shell=KILLED + 'cp o.h5.journal keep; "$MPM1D" in.nml scene.velocity_amplitude=0.2 --resume; rc=$?; '
          'cmp -s keep o.h5.journal || exit 9; exit $rc')
