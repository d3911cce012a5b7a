!> Parameter sweeps: the &sweep namelist group, the table of cases (every combination of the
!> lists), and running them in parallel with OpenMP (one case per thread at a time, dynamic
!> schedule). Each case writes only its own slot, so results do not depend on the thread count.
!> An error pass runs every case once; an optional timing pass repeats each case until a minimum
!> measured time is reached and keeps the median time per run.
!> A signal (SIGINT, SIGTERM, SIGHUP) caught during the passes stops the sweep: no case starts any more,
!> the running ones are abandoned at their next step (status not_run again, no value), and the
!> caller writes what was finished; a later run resumes the cases still not run (or not timed).
module mpm_sweep
   use, intrinsic :: ieee_arithmetic, only: ieee_is_finite
   use, intrinsic :: iso_fortran_env, only: int8
   use omp_lib, only: omp_get_wtime, omp_get_max_threads
   use mpm_kinds, only: dp, i8
   use mpm_errors, only: error_t, set_error, append_error
   use mpm_strings, only: str, lower
   use mpm_config, only: config_t, read_config_text, input_name, validate_config, resolve_config, &
                         config_parameters, config_groups, other_kind_list, new_config, assign_in_place, known_kind, &
                        run_length_flags
   use mpm_registry, only: parameter_t, nml_item_t, value_list_t, real_entry, int_entry, logical_entry, &
                           parse_namelist, read_input_text, add_overrides, item_place, read_value_list, &
                           single_value_list, set_from_list, set_parameter, &
                           check_parameter, find_parameter, entry_names, format_value, list_text, quoted, &
                           type_real, type_int, used_by, sweep_name_hint
   use mpm_simulation, only: run_result_t, run_simulation, guard_trip_t, guard_message
   use mpm_diagnostics, only: history_t, status_ok, status_setup_failed, status_not_run, no_value
   use mpm_files, only: catch_interrupts, release_interrupts, interrupt_signal, wait_for_signal
   use mpm_progress, only: progress_t
   use mpm_sort, only: sort_order, median, relative_spread
   use mpm_journal, only: journal_t, journal_record_t, journal_append
   implicit none
   private
   public :: sweep_config_t, sweep_case_t, sweep_t, read_sweep, read_sweep_text, sweep_cases, run_sweep
   public :: has_sweep_group, has_sweep_text, case_config, max_threads, shard_file, sweep_output_file
   public :: cases_done, cases_timed, cases_to_time, case_cost, shard_cases
   public :: apply_record

   !> The records of a sweep's journal (mpm_journal): its identity (the first record), a case that ran
   !> (its row and history), a case timed (its timing columns).
   integer, parameter, public :: record_sweep = 1, record_case = 2, record_timing = 3

   !> Timing pass: a round of repeats whose middle half spans more than this fraction of its median
   !> was disturbed (another process, frequency changes) and is measured again, up to max_rounds
   !> rounds; the round with the smallest spread is kept, and its spread stored for the reader.
   real(dp), parameter :: noisy_spread = 0.2_dp
   integer, parameter :: max_rounds = 3

   !> Most threads a sweep asks for (OpenMP runtimes fail far below 10^5 threads; no node has more cores).
   integer, parameter :: max_threads = 4096
   public :: sweep_parameters, case_columns, case_weights

   !> The &sweep group: lists to combine and how to run them.
   type :: sweep_config_t
      !> One list per sweepable variable of the registry, in the registry's order (the last list
      !> varies fastest); a list left out holds the base value alone.
      type(value_list_t), allocatable :: lists(:)
      !> Timing pass: repeat each case until this much run time is measured (s); 0 switches it off.
      real(dp) :: min_time = 0.02_dp
      !> Threads for the error pass (0: OMP_NUM_THREADS or all cores) and for the timing pass.
      integer :: threads = 0
      integer :: timing_threads = 1
      !> Keep per-case histories (u_cm, energies per step) in the sweep file.
      logical :: histories = .false.
      !> Show a progress line on standard error (only when it is a terminal).
      logical :: progress = .true.
      !> This process runs shard `shard` of `shards` (cases shard, shard+shards, ...).
      integer :: shard = 1
      integer :: shards = 1
      character(len=:), allocatable :: namelist_text
   end type sweep_config_t

   !> One case of the sweep and what it produced. A result that does not exist is no_value (NaN):
   !> every result of a case not run; max_error and relative_error of a case a guard stopped (the
   !> error reached up to the stop is in error_before_stop and relative_error_before_stop, no value
   !> for a completed case); the run time of a case not timed (repeats = 0).
   type :: sweep_case_t
      !> Position in the full (unsharded) table, 1-based; it gives the value of every list.
      integer :: index = 0
      integer :: steps = 0, particles = 0
      !> Runs timed for run_time (0: not timed: no timing pass, stopped by a guard, or interrupted).
      integer :: repeats = 0
      integer :: status = status_not_run
      real(dp) :: dt = 0.0_dp, max_error = no_value, relative_error = no_value, run_time = no_value
      real(dp) :: error_before_stop = no_value, relative_error_before_stop = no_value
      !> Timing pass: relative spread (interquartile range / median) of the kept round of repeats,
      !> and the rounds measured (a round whose spread exceeds noisy_spread is measured again).
      real(dp) :: run_time_spread = no_value
      integer :: timing_rounds = 0
      real(dp) :: max_energy_ratio = no_value, final_energy_ratio = no_value
      real(dp) :: min_volume_ratio = no_value, max_cell_move = no_value, min_node_mass_ratio = no_value
      character(len=:), allocatable :: message !< why the case failed (made after the parallel loop)
      type(guard_trip_t) :: trip
      type(history_t) :: history
   end type sweep_case_t

   !> What makes a case's configuration: a configuration and the parameter table pointing into it,
   !> built once per sweep (the table is an array of about 60 entries of 1.4 kB with their help texts:
   !> built per case, four times per case, it cost the paper's Table-2 sweep 3 % of its instructions).
   !> With the table of the defaults (new_config of the sweep's kind), which validating a case compares with.
   type :: case_builder_t
      type(config_t) :: config, defaults
      type(parameter_t), allocatable :: table(:), default_table(:)
   end type case_builder_t

   !> A sweep: the base configuration, the &sweep group, this shard's cases and the timings.
   type :: sweep_t
      type(config_t) :: base
      type(sweep_config_t) :: settings
      type(sweep_case_t), allocatable :: cases(:)
      integer :: total_cases = 0
      integer :: threads_used = 0
      real(dp) :: error_pass_time = 0.0_dp, timing_pass_time = 0.0_dp, wall_time = 0.0_dp
      !> The signal that interrupted the sweep (2 SIGINT, 15 SIGTERM, 1 SIGHUP), 0 if none; and in
      !> which pass (the timing pass: every case ran, some are not timed).
      integer :: interrupted_by = 0
      logical :: interrupted_timing = .false.
      !> Made when the sweep's cases are made (sweep_cases) and shared by copies of the sweep;
      !> case_config writes into it, so its callers take turns (the error and timing passes call it in
      !> a critical section). Without it case_config builds a table of its own.
      type(case_builder_t), pointer :: builder => null()
      !> Where each finished case is appended as it finishes (mpm_sweep_output opens it; not open: none).
      type(journal_t) :: journal
      !> A resumed sweep: the cases (and records of cases and timings) its journal gave, the bytes of its
      !> whole records, and the bytes of a torn last record dropped.
      integer :: journal_cases = 0, journal_records = 0
      integer(i8) :: journal_bytes = 0, journal_torn = 0
   end type sweep_t

contains

   !> Does namelist `text` contain a &sweep group?
   logical function has_sweep_text(text)
      character(len=*), intent(in) :: text
      type(nml_item_t), allocatable :: items(:)
      character(len=32), allocatable :: groups(:)
      integer, allocatable :: lines(:)
      type(error_t), allocatable :: error
      call parse_namelist(text, '', items, groups, lines, error)
      has_sweep_text = any(groups == 'sweep')
   end function has_sweep_text

   !> Does the namelist file contain a &sweep group?
   logical function has_sweep_group(path)
      character(len=*), intent(in) :: path
      character(len=4096) :: line
      integer :: unit, stat, k
      has_sweep_group = .false.
      open (newunit=unit, file=path, status='old', action='read', iostat=stat)
      if (stat /= 0) return
      do
         read (unit, '(a)', iostat=stat) line
         if (stat /= 0) exit
         k = index(lower(line), '&sweep')
         if (k > 0) then
            if (index(line(1:k), '!') == 0) then
               has_sweep_group = .true.
               exit
            end if
         end if
      end do
      close (unit)
   end function has_sweep_group

   !> The registry entries of the &sweep group's run settings (its lists come from the sweepable
   !> entries of the run's registry).
   subroutine sweep_parameters(settings, table)
      type(sweep_config_t), intent(inout), target :: settings
      type(parameter_t), allocatable, intent(out) :: table(:)
      table = [ &
         real_entry('sweep', 'min_time', settings%min_time, 's', 'timing pass: repeat each case until this much '// &
                    'run time is measured; 0: no timing pass', at_least=0.0_dp, at_most=3600.0_dp), &
         int_entry('sweep', 'threads', settings%threads, 'threads of the error pass', at_least=0, &
                   at_most=max_threads, note='0: OMP_NUM_THREADS or all cores'), &
         int_entry('sweep', 'timing_threads', settings%timing_threads, 'threads of the timing pass', at_least=1, &
                   at_most=max_threads), &
         logical_entry('sweep', 'histories', settings%histories, 'keep each case''s history in the sweep file'), &
         logical_entry('sweep', 'progress', settings%progress, 'progress on standard error: a line redrawn '// &
                       'on a terminal, a line a minute in a log'), &
         int_entry('sweep', 'shard', settings%shard, 'this process runs cases shard, shard+shards, ...', at_least=1), &
         int_entry('sweep', 'shards', settings%shards, 'the number of shards the sweep is cut into', at_least=1)]
   end subroutine sweep_parameters

   !> Read the base groups and &sweep from `path` ('-': standard input), validate everything, build
   !> this shard's cases. `shard_override`/`shards_override` (> 0), `threads_override` (>= 0) and
   !> `overrides` (`group.name=value`, e.g. sweep.elements=10,20) come from the command line.
   subroutine read_sweep(path, study, error, shard_override, shards_override, threads_override, overrides)
      character(len=*), intent(in) :: path
      type(sweep_t), intent(out), target :: study
      type(error_t), allocatable, intent(out) :: error
      integer, intent(in) :: shard_override, shards_override, threads_override
      character(len=*), intent(in), optional :: overrides(:)
      character(len=:), allocatable :: text
      call read_input_text(path, text, error)
      if (allocated(error)) return
      if (present(overrides)) then
         call read_sweep_text(text, input_name(path), study, error, shard_override, &
                              shards_override, threads_override, overrides)
      else
         call read_sweep_text(text, input_name(path), study, error, shard_override, &
                              shards_override, threads_override, [character(len=1) ::])
      end if
   end subroutine read_sweep

   !> read_sweep of namelist `text` read from `path` (named so in messages).
   subroutine read_sweep_text(text, path, study, error, shard_override, shards_override, threads_override, overrides)
      character(len=*), intent(in) :: text, path
      type(sweep_t), intent(out), target :: study
      type(error_t), allocatable, intent(out) :: error
      integer, intent(in) :: shard_override, shards_override, threads_override
      character(len=*), intent(in) :: overrides(:)
      type(parameter_t), allocatable :: base(:), settings(:)
      type(nml_item_t), allocatable :: items(:)
      character(len=32), allocatable :: groups(:)
      integer, allocatable :: group_lines(:), lines(:)
      integer :: i, j, k
      character(len=:), allocatable :: where
      type(config_t), target :: defaults
      type(error_t), allocatable :: syntax_error

      ! The base groups' problems (syntax included) and the &sweep group's are reported together.
      call read_config_text(text, path, study%base, error, extra_groups=['sweep'], overrides=overrides)
      call parse_namelist(text, path, items, groups, group_lines, syntax_error)
      if (allocated(syntax_error) .and. .not. allocated(error)) error = syntax_error
      if (size(overrides) > 0) then
         call add_overrides(items, overrides, [character(len=16) :: config_groups, 'sweep'], syntax_error)
         if (allocated(syntax_error) .and. .not. allocated(error)) error = syntax_error
      end if
      defaults = study%base
      call config_parameters(defaults, base)
      call sweep_parameters(study%settings, settings)
      allocate (study%settings%lists(0))
      do k = 1, size(base)
         if (len_trim(base(k)%sweep_list) == 0) cycle
         study%settings%lists = [study%settings%lists, single_value_list(base(k), trim(base(k)%sweep_list))]
         study%settings%lists(size(study%settings%lists))%entry = k
      end do
      allocate (lines(size(study%settings%lists)))
      lines = 0
      do i = 1, size(items)
         if (items(i)%group /= 'sweep') cycle
         where = item_place(items(i), path)
         j = list_named(items(i)%name)
         if (j > 0) then
            if (lines(j) > 0) then
               call append_error(error, where//"sweep: list '"//trim(study%settings%lists(j)%name)// &
                                 "' is given twice (as '"//items(i)%name//"', also line "//str(lines(j))//")")
               cycle
            end if
            lines(j) = items(i)%line
            k = study%settings%lists(j)%entry
            call read_value_list(base(k), items(i)%name, items(i)%values, where, study%settings%lists(j), error)
            study%settings%lists(j)%entry = k
            study%settings%lists(j)%name = base(k)%sweep_list  ! the list's name, whichever name was given
            cycle
         end if
         k = find_parameter(settings, 'sweep', items(i)%name)
         if (k == 0) then
            ! a list of another kind's variable (asked only of a name that is no setting of the sweep: the
            ! question builds every kind's catalog), else unknown
            if (len(other_kind_list(study%base, items(i)%name)) > 0) then
               if (known_kind(study%base%scene_kind)) call append_error(error, where//"sweep: list '"// &
                  items(i)%name//"' varies "//other_kind_list(study%base, items(i)%name))
            else
               call append_error(error, where//"group &sweep: unknown variable '"//items(i)%name//"'"// &
                                 sweep_name_hint(items(i)%name, list_names()//", "//entry_names(settings, 'sweep'), &
                                                 base))
            end if
         else if (settings(k)%line > 0) then
            call append_error(error, where//"sweep: '"//items(i)%name//"' is given twice (also line "// &
                              str(settings(k)%line)//")")
         else
            settings(k)%line = items(i)%line
            call set_parameter(settings(k), items(i)%values, where, error)
         end if
      end do
      if (shards_override > 0) then
         study%settings%shard = shard_override
         study%settings%shards = shards_override
      end if
      if (threads_override >= 0) study%settings%threads = threads_override
      do k = 1, size(settings)
         call check_parameter(settings(k), error)
      end do
      associate (s => study%settings)
         if (s%shard > s%shards) call append_error(error, "sweep: shard = "//str(s%shard)//" of shards = "// &
                                                   str(s%shards)//" is out of range; allowed: 1 <= shard <= shards")
         if (product(int([(s%lists(j)%size(), j=1, size(s%lists))], i8)) > 10000000_i8) &
            call append_error(error, "sweep: the lists give more than 10^7 cases; allowed: at most 10^7")
      end associate
      if (allocated(error)) return
      study%settings%namelist_text = sweep_namelist(study%settings)
      call sweep_cases(study, error)
   contains
      integer function list_named(name)
         character(len=*), intent(in) :: name
         integer :: m
         list_named = 0
         do m = 1, size(study%settings%lists)
            if (study%settings%lists(m)%name == name) list_named = m
            if (len_trim(study%settings%lists(m)%alias) > 0 .and. study%settings%lists(m)%alias == name) &
               list_named = m
         end do
      end function list_named
      function list_names() result(names)
         character(len=:), allocatable :: names
         integer :: m
         names = ''
         do m = 1, size(study%settings%lists)
            if (m > 1) names = names//', '
            names = names//trim(study%settings%lists(m)%name)
         end do
      end function list_names
   end subroutine read_sweep_text

   !> The value number of every list in case `index` (mixed radix over the lists, the last fastest): one
   !> division per list, from the last.
   pure function list_positions(lists, index) result(at)
      type(value_list_t), intent(in) :: lists(:)
      integer, intent(in) :: index
      integer :: at(size(lists))
      integer :: j, n
      integer(i8) :: rest
      rest = index - 1
      do j = size(lists), 1, -1
         n = lists(j)%size()
         at(j) = int(mod(rest, int(n, i8))) + 1
         rest = rest/n
      end do
   end function list_positions

   !> The configuration of one case: the base with the case's value of every list, resolved.
   function case_config(sweep, c) result(config)
      type(sweep_t), intent(in) :: sweep
      type(sweep_case_t), intent(in) :: c
      type(config_t) :: config
      type(config_t), target :: local
      type(parameter_t), allocatable :: table(:)
      if (associated(sweep%builder)) then
         ! the base's values into the builder's configuration, in place, so that the table's pointers
         ! stay on them
         call assign_in_place(sweep%builder%config, sweep%base)
         call run_length_flags(sweep%builder%config)
         call set_case_values(sweep%builder%table, sweep%builder%config)
         config = sweep%builder%config
      else
         local = sweep%base
         call config_parameters(local, table)
         call set_case_values(table, local)
         config = local
      end if
   contains
      !> The case's values of the lists into `into` through `table`, then the derived quantities.
      subroutine set_case_values(table, into)
         type(parameter_t), intent(inout) :: table(:)
         type(config_t), intent(inout) :: into
         integer :: j
         integer :: at(size(sweep%settings%lists))
         at = list_positions(sweep%settings%lists, c%index)
         do j = 1, size(sweep%settings%lists)
            associate (list => sweep%settings%lists(j))
               call set_from_list(table(list%entry), list, at(j))
            end associate
         end do
         into%snapshot_count = 0
         into%snapshot_every = 0
         into%checkpoint_steps = 0
         call resolve_config(into)
      end subroutine set_case_values
   end function case_config

   !> List `j`'s values over `cases` (a /cases column).
   function case_column(sweep, j, cases) result(column)
      type(sweep_t), intent(in) :: sweep
      integer, intent(in) :: j
      type(sweep_case_t), intent(in) :: cases(:)
      type(value_list_t) :: column
      type(value_list_t), allocatable :: columns(:)
      columns = case_columns(sweep, [j], cases)
      column = columns(1)
   end function case_column

   !> The values of lists `which` over `cases` (/cases columns), each case's positions in the lists
   !> found once for all of them.
   function case_columns(sweep, which, cases) result(columns)
      type(sweep_t), intent(in) :: sweep
      integer, intent(in) :: which(:)
      type(sweep_case_t), intent(in) :: cases(:)
      type(value_list_t), allocatable :: columns(:)
      integer, allocatable :: at(:, :)
      integer :: i, m
      allocate (at(size(sweep%settings%lists), size(cases)), columns(size(which)))
      do i = 1, size(cases)
         at(:, i) = list_positions(sweep%settings%lists, cases(i)%index)
      end do
      do m = 1, size(which)
         associate (list => sweep%settings%lists(which(m)), column => columns(m))
            column = list
            column%reals = list%reals(at(which(m), :))
            column%ints = list%ints(at(which(m), :))
            column%texts = list%texts(at(which(m), :))
         end associate
      end do
   end function case_columns

   !> Build this shard's cases (every combination; the last list varies fastest) and validate
   !> each one as a single run would be validated.
   subroutine sweep_cases(sweep, error)
      type(sweep_t), intent(inout) :: sweep
      type(error_t), allocatable, intent(inout) :: error
      integer :: j, n, mine
      type(sweep_case_t) :: one
      type(config_t) :: config
      type(error_t), allocatable :: case_error
      associate (s => sweep%settings)
         sweep%total_cases = product([(s%lists(j)%size(), j=1, size(s%lists))])
         if (s%shards > sweep%total_cases) then
            call append_error(error, "sweep: shards = "//str(s%shards)//" is more than the sweep's "// &
                              str(sweep%total_cases)//" cases (a shard would have none); allowed: shards <= "// &
                              str(sweep%total_cases))
            return
         end if
         allocate (sweep%cases(shard_cases(sweep%total_cases, s%shard, s%shards)))
         if (.not. associated(sweep%builder)) then
            allocate (sweep%builder)
            sweep%builder%config = sweep%base
            sweep%builder%defaults = new_config(sweep%base%scene_kind)
            call config_parameters(sweep%builder%config, sweep%builder%table)
            call config_parameters(sweep%builder%defaults, sweep%builder%default_table)
         end if
         mine = 0
         do n = s%shard, sweep%total_cases, s%shards
            one = sweep_case_t(index=n)
            config = case_config(sweep, one)
            config%history = s%histories
            ! (the builder's configuration holds the case: its table is the case's)
            sweep%builder%config%history = s%histories
            call validate_config(sweep%builder%config, case_error, with_system=.false., &
                                 default_table=sweep%builder%default_table, table=sweep%builder%table)
            if (allocated(case_error)) then
               call append_error(error, "sweep case "//str(n)//" ("//case_values(n)//"): "//case_error%message)
               deallocate (case_error)
               if (count_lines(error%message) > 20) return
            end if
            one%steps = config%steps
            one%dt = config%dt
            one%particles = config%elements*config%particles_per_element
            mine = mine + 1
            sweep%cases(mine) = one
         end do
         if (allocated(error) .or. mine == 0) return
         ! The machine checks (memory, output folder) once, for the largest cases.
         call check_system(maxloc(sweep%cases(1:mine)%particles, 1))
         if (s%histories) call check_system(maxloc(sweep%cases(1:mine)%steps, 1))
      end associate
   contains
      subroutine check_system(i)
         integer, intent(in) :: i
         type(config_t) :: largest
         largest = case_config(sweep, sweep%cases(i))
         largest%history = sweep%settings%histories
         call validate_config(largest, error)
      end subroutine check_system
      !> The values of the lists with more than one value, for messages.
      function case_values(index) result(text)
         integer, intent(in) :: index
         character(len=:), allocatable :: text
         type(value_list_t) :: one_value
         integer :: m
         text = ''
         do m = 1, size(sweep%settings%lists)
            if (sweep%settings%lists(m)%size() < 2) cycle
            one_value = case_column(sweep, m, [sweep_case_t(index=index)])
            if (len(text) > 0) text = text//', '
            text = text//trim(one_value%column)//'='//list_text(one_value)
         end do
      end function case_values
   end subroutine sweep_cases

   integer function count_lines(text)
      character(len=*), intent(in) :: text
      integer :: i
      count_lines = 1
      do i = 1, len(text)
         if (text(i:i) == new_line('a')) count_lines = count_lines + 1
      end do
   end function count_lines

   !> Run the error pass (every case not run yet, in parallel) and, when min_time > 0, the timing pass
   !> (every completed case not timed yet). A sweep read afresh runs every case; one continued from
   !> its file (resume) only what is left. With `catch_signals`, SIGINT, SIGTERM and SIGHUP stop the
   !> passes (sweep%interrupted_by) instead of ending the process.
   !> Test hook: MPM1D_PAUSE_AFTER_CASES=N makes the thread that finishes the N-th case (counted over
   !> both passes, in the order they finish; threads = 1 for a known set) create the file mpm1d_paused
   !> in the working folder and wait there for a signal (at most 600 s), so that a test signals a sweep
   !> at a known point.
   subroutine run_sweep(sweep, catch_signals)
      type(sweep_t), intent(inout) :: sweep
      logical, intent(in), optional :: catch_signals
      integer, allocatable :: order(:)
      integer :: threads, pause_after
      real(dp) :: start, seconds_per_cost, error_pass
      logical :: catching

      catching = .false.
      if (present(catch_signals)) catching = catch_signals
      if (catching) call catch_interrupts()
      pause_after = pause_hook()
      start = omp_get_wtime()
      threads = sweep%settings%threads
      if (threads == 0) threads = omp_get_max_threads()
      sweep%threads_used = threads
      order = by_decreasing_cost(sweep%cases)
      order = pack(order, sweep%cases(order)%status == status_not_run)
      call over_cases(sweep, order, threads, case_weights(sweep%cases, 0.0_dp, 0.0_dp), .false., pause_after)
      call describe_failures(sweep)
      error_pass = omp_get_wtime() - start
      ! (added: a resumed sweep's file brings the time of its earlier passes)
      sweep%error_pass_time = sweep%error_pass_time + error_pass
      sweep%interrupted_by = interrupt_signal()
      if (sweep%settings%min_time > 0.0_dp .and. sweep%interrupted_by == 0) then
         ! the error pass gives the seconds per particle-step on this machine (thread-seconds / cost)
         seconds_per_cost = error_pass*threads/max(1.0_dp, sum(case_cost(sweep%cases(order))))
         pause_after = pause_after - size(order)
         order = by_decreasing_cost(sweep%cases)
         order = pack(order, cases_to_time(sweep%cases(order)))
         call over_cases(sweep, order, sweep%settings%timing_threads, case_weights(sweep%cases, seconds_per_cost, &
                         sweep%settings%min_time), .true., pause_after)
         sweep%timing_pass_time = sweep%timing_pass_time + (omp_get_wtime() - start - error_pass)
         sweep%interrupted_by = interrupt_signal()
         sweep%interrupted_timing = sweep%interrupted_by /= 0
      end if
      sweep%wall_time = sweep%wall_time + (omp_get_wtime() - start)
      if (catching) call release_interrupts()
   end subroutine run_sweep

   !> MPM1D_PAUSE_AFTER_CASES as a number (0 when unset or not a number).
   integer function pause_hook()
      character(len=16) :: text
      integer :: length, stat
      pause_hook = 0
      call get_environment_variable('MPM1D_PAUSE_AFTER_CASES', text, length=length)
      if (length == 0) return
      read (text, *, iostat=stat) pause_hook
      if (stat /= 0) pause_hook = 0
   end function pause_hook

   !> The cases at positions `order` (expensive first, so that the dynamic schedule ends evenly):
   !> each once, or (timing) each repeated until min_time. Each case writes only its own slot. Once a
   !> signal is caught no case starts; running ones stop at their next step and stay not run.
   subroutine over_cases(sweep, order, threads, weights, timing, pause_after)
      type(sweep_t), intent(inout) :: sweep
      integer, intent(in) :: order(:), threads, pause_after
      real(dp), intent(in) :: weights(:)
      logical, intent(in) :: timing
      type(progress_t) :: progress
      type(config_t) :: config
      integer :: k, finished, mine
      finished = 0
      call progress%start(merge('timing pass', 'error pass ', timing), weights(order), sweep%settings%progress)
      !$omp parallel do default(none) schedule(dynamic, 1) num_threads(threads) &
      !$omp shared(sweep, order, progress, timing, weights, pause_after, finished) &
      !$omp private(config, k, mine)
      do k = 1, size(order)
         if (interrupt_signal() /= 0) cycle
         ! one thread at a time builds a case's configuration: case_config fills the parameter table (an
         ! array constructor of a type with pointer components), and with two threads doing so at once
         ! gfortran 12's code corrupted memory now and then (about one paper sweep in 150 ran a case on
         ! the wrong path; test_thread_safety repeats a sweep and compares it bit for bit)
         !$omp critical (mpm_case_config)
         config = case_config(sweep, sweep%cases(order(k)))
         !$omp end critical (mpm_case_config)
         if (timing) then
            call time_case(config, sweep%settings%min_time, sweep%cases(order(k)))
         else
            call run_case(config, sweep%settings%histories, sweep%cases(order(k)))
         end if
         call journal_case(sweep%journal, sweep%cases(order(k)), timing)
         if (interrupt_signal() /= 0) cycle
         call progress%advance(weights(order(k)))
         if (pause_after > 0) then
            !$omp atomic capture
            finished = finished + 1
            mine = finished
            !$omp end atomic
            if (mine == pause_after) call wait_for_signal(600, 'mpm1d_paused')
         end if
      end do
      !$omp end parallel do
      call progress%finish()
   end subroutine over_cases

   !> Append a finished case to the journal (when one is open): its row and history after the error
   !> pass, its timing after the timing pass; a case a signal abandoned is not finished. Its record is
   !> made by the case's thread, written by one thread at a time.
   subroutine journal_case(journal, c, timing)
      type(journal_t), intent(inout) :: journal
      type(sweep_case_t), intent(in) :: c
      logical, intent(in) :: timing
      integer(int8), allocatable :: record(:)
      integer :: kind
      if (journal%fd < 0) return
      if (timing .and. c%repeats > 0) then
         kind = record_timing
         record = [transfer([c%index, c%repeats, c%timing_rounds], [0_int8]), &
                   transfer([c%run_time, c%run_time_spread], [0_int8])]
      else if (.not. timing .and. c%status /= status_not_run) then
         kind = record_case
         record = case_record(c)
      else
         return
      end if
      !$omp critical (mpm_journal)
      call journal_append(journal, kind, record)
      !$omp end critical (mpm_journal)
   end subroutine journal_case

   !> A case's row and history as bytes: 7 integers (index, steps, particles, status, repeats,
   !> timing_rounds, the history's length n), 12 reals, the guard's trip as it is in memory, then the
   !> history's 5 columns of n values (apply_record reads them back).
   function case_record(c) result(bytes)
      type(sweep_case_t), intent(in) :: c
      integer(int8), allocatable :: bytes(:)
      integer, parameter :: real_bytes = storage_size(0.0_dp)/8
      integer(int8), allocatable :: head(:)
      integer :: n, at
      n = c%history%recorded
      head = [transfer([c%index, c%steps, c%particles, c%status, c%repeats, c%timing_rounds, n], [0_int8]), &
              transfer(case_reals(c), [0_int8]), transfer(c%trip, [0_int8])]
      allocate (bytes(size(head) + 5*n*real_bytes))
      bytes(1:size(head)) = head
      at = size(head)
      if (n == 0) return
      call put(c%history%time(0:n - 1))
      call put(c%history%ucm(0:n - 1))
      call put(c%history%ucm_exact(0:n - 1))
      call put(c%history%kinetic_energy(0:n - 1))
      call put(c%history%strain_energy(0:n - 1))
   contains
      subroutine put(values)
         real(dp), intent(in) :: values(:)
         bytes(at + 1:at + size(values)*real_bytes) = transfer(values, bytes)
         at = at + size(values)*real_bytes
      end subroutine put
   end function case_record

   !> The real columns of a case's row, in the journal's order.
   pure function case_reals(c) result(reals)
      type(sweep_case_t), intent(in) :: c
      real(dp) :: reals(12)
      reals = [c%dt, c%max_error, c%relative_error, c%run_time, c%error_before_stop, c%relative_error_before_stop, &
               c%run_time_spread, c%max_energy_ratio, c%final_energy_ratio, c%min_volume_ratio, c%max_cell_move, &
               c%min_node_mass_ratio]
   end function case_reals

   !> Put a case or timing record of the sweep's journal back into its case (the record's case must be
   !> one of this shard's: an error names it otherwise).
   subroutine apply_record(sweep, record, error)
      type(sweep_t), intent(inout) :: sweep
      type(journal_record_t), intent(in) :: record
      type(error_t), allocatable, intent(out) :: error
      integer, parameter :: int_bytes = storage_size(0)/8, real_bytes = storage_size(0.0_dp)/8
      integer :: ints(7), i, n, trip_bytes, at
      real(dp) :: reals(12)
      type(guard_trip_t) :: trip
      trip_bytes = size(transfer(trip, [0_int8]))
      associate (bytes => record%payload)
         select case (record%kind)
         case (record_case)
            if (size(bytes) < 7*int_bytes) then
               call malformed()
               return
            end if
            ints = transfer(bytes(1:7*int_bytes), ints)
            n = ints(7)
            if (n < 0 .or. size(bytes, kind=i8) /= 7*int_bytes + 12*real_bytes + trip_bytes + 5_i8*n*real_bytes) then
               call malformed()
               return
            end if
            i = position(ints(1))
            if (i == 0) return
            at = 7*int_bytes
            reals = transfer(bytes(at + 1:at + 12*real_bytes), reals)
            at = at + 12*real_bytes
            trip = transfer(bytes(at + 1:at + trip_bytes), trip)
            at = at + trip_bytes
            associate (c => sweep%cases(i))
               c%steps = ints(2)
               c%particles = ints(3)
               c%status = ints(4)
               c%repeats = ints(5)
               c%timing_rounds = ints(6)
               c%dt = reals(1)
               c%max_error = reals(2)
               c%relative_error = reals(3)
               c%run_time = reals(4)
               c%error_before_stop = reals(5)
               c%relative_error_before_stop = reals(6)
               c%run_time_spread = reals(7)
               c%max_energy_ratio = reals(8)
               c%final_energy_ratio = reals(9)
               c%min_volume_ratio = reals(10)
               c%max_cell_move = reals(11)
               c%min_node_mass_ratio = reals(12)
               c%trip = trip
               if (allocated(c%message)) deallocate (c%message) ! (made again from the trip)
               c%history = history_t()
               c%history%recorded = n
               if (n > 0) then
                  allocate (c%history%time(0:n - 1), c%history%ucm(0:n - 1), c%history%ucm_exact(0:n - 1), &
                            c%history%kinetic_energy(0:n - 1), c%history%strain_energy(0:n - 1))
                  call column(c%history%time)
                  call column(c%history%ucm)
                  call column(c%history%ucm_exact)
                  call column(c%history%kinetic_energy)
                  call column(c%history%strain_energy)
               end if
            end associate
         case (record_timing)
            if (size(bytes) /= 3*int_bytes + 2*real_bytes) then
               call malformed()
               return
            end if
            ints(1:3) = transfer(bytes(1:3*int_bytes), ints(1:3))
            reals(1:2) = transfer(bytes(3*int_bytes + 1:), reals(1:2))
            i = position(ints(1))
            if (i == 0) return
            sweep%cases(i)%repeats = ints(2)
            sweep%cases(i)%timing_rounds = ints(3)
            sweep%cases(i)%run_time = reals(1)
            sweep%cases(i)%run_time_spread = reals(2)
         case default
            call malformed()
         end select
      end associate
   contains
      !> The position in this shard's cases of case `index`, 0 (and an error) when it is not one of them.
      integer function position(index)
         integer, intent(in) :: index
         associate (s => sweep%settings)
            position = 0
            if (index >= s%shard .and. mod(index - s%shard, s%shards) == 0) position = (index - s%shard)/s%shards + 1
            if (position > size(sweep%cases)) position = 0
            if (position > 0) then
               if (sweep%cases(position)%index /= index) position = 0
            end if
         end associate
         if (position == 0) call set_error(error, 'a record of case '//str(index)//', which is not a case of '// &
                                           'this sweep (or shard)')
      end function position
      subroutine column(values)
         real(dp), intent(out) :: values(0:)
         values = transfer(record%payload(at + 1:at + size(values)*real_bytes), values)
         at = at + size(values)*real_bytes
      end subroutine column
      subroutine malformed()
         call set_error(error, 'a record of kind '//str(record%kind)//' and '//str(size(record%payload))// &
                        ' bytes, which this build does not write')
      end subroutine malformed
   end subroutine apply_record

   !> The cases done: run to their end or stopped by a guard (not the ones not run).
   pure integer function cases_done(cases)
      type(sweep_case_t), intent(in) :: cases(:)
      cases_done = count(cases%status /= status_not_run)
   end function cases_done

   !> The cases timed (repeats > 0).
   pure integer function cases_timed(cases)
      type(sweep_case_t), intent(in) :: cases(:)
      cases_timed = count(cases%repeats > 0)
   end function cases_timed

   !> Which cases the timing pass measures: those completed and not timed yet.
   elemental logical function cases_to_time(c)
      type(sweep_case_t), intent(in) :: c
      cases_to_time = c%status == status_ok .and. c%repeats == 0
   end function cases_to_time

   !> Messages of the failed cases, made here, serially (see guard_message).
   subroutine describe_failures(sweep)
      type(sweep_t), intent(inout) :: sweep
      integer :: i
      do i = 1, size(sweep%cases)
         associate (c => sweep%cases(i))
            if (allocated(c%message)) cycle ! read back from the file a resumed sweep continues
            if (c%status == status_setup_failed) then
               c%message = 'the run could not be set up: not enough memory for '//str(c%particles)//' particles'
            else if (c%status /= status_ok .and. c%status /= status_not_run) then
               c%message = guard_message(c%status, c%trip, case_config(sweep, c))
            end if
         end associate
      end do
   end subroutine describe_failures

   !> Run one case and store its summary (and history, if asked) in its own slot.
   subroutine run_case(case, keep_history, c)
      type(config_t), intent(in) :: case
      logical, intent(in) :: keep_history
      type(sweep_case_t), intent(inout) :: c
      type(config_t) :: config
      type(run_result_t) :: result
      type(error_t), allocatable :: error
      config = case
      config%history = keep_history
      call run_simulation(config, result, error, record_history=keep_history)
      if (allocated(error)) then
         c%status = status_setup_failed
         return
      end if
      if (result%status == status_not_run) return ! abandoned (a signal): no result
      c%status = result%status
      c%trip = result%trip
      if (result%status == status_ok) then
         c%max_error = result%max_error
         c%relative_error = result%relative_error
      else
         c%error_before_stop = result%max_error
         c%relative_error_before_stop = result%relative_error
      end if
      c%max_energy_ratio = result%max_energy_ratio
      if (result%initial_energy > 0.0_dp) then
         c%final_energy_ratio = result%final_energy/result%initial_energy
      else
         c%final_energy_ratio = 1.0_dp
      end if
      c%min_volume_ratio = result%min_volume_ratio
      c%max_cell_move = result%max_cell_move
      c%min_node_mass_ratio = result%min_node_mass_ratio
      if (keep_history) call move_alloc_history(result%history, c%history)
   end subroutine run_case

   subroutine move_alloc_history(from, to)
      type(history_t), intent(inout) :: from
      type(history_t), intent(out) :: to
      to%recorded = from%recorded
      call move_alloc(from%time, to%time)
      call move_alloc(from%ucm, to%ucm)
      call move_alloc(from%ucm_exact, to%ucm_exact)
      call move_alloc(from%kinetic_energy, to%kinetic_energy)
      call move_alloc(from%strain_energy, to%strain_energy)
   end subroutine move_alloc_history



   !> Repeat one case (set-up and time loop, no output) until min_time of measured run time is
   !> reached (at least 3 runs) and keep the median time per run. Failed cases are not timed; a case
   !> interrupted (a signal) keeps no time (repeats 0, run_time no value).
   subroutine time_case(case, min_time, c)
      type(config_t), intent(in) :: case
      real(dp), intent(in) :: min_time
      type(sweep_case_t), intent(inout) :: c
      integer, parameter :: min_repeats = 3, max_repeats = 100000
      type(config_t) :: config
      type(run_result_t) :: result
      type(error_t), allocatable :: error
      real(dp), allocatable :: times(:)
      real(dp) :: total, spread, best_spread, best_time
      integer :: n, round, rounds, best_repeats
      if (c%status /= status_ok) return
      config = case
      config%history = .false.
      allocate (times(max_repeats))
      best_spread = huge(1.0_dp)
      best_repeats = 0
      best_time = no_value
      rounds = 0
      do round = 1, max_rounds
         total = 0.0_dp
         n = 0
         do while ((total < min_time .or. n < min_repeats) .and. n < max_repeats)
            call run_simulation(config, result, error, record_history=.false.)
            if (allocated(error)) return
            if (result%status == status_not_run) return ! interrupted: no time
            n = n + 1
            times(n) = result%run_time
            total = total + result%run_time
         end do
         spread = relative_spread(times(1:n))
         rounds = round
         if (spread < best_spread) then
            best_repeats = n
            best_time = median(times(1:n))
            best_spread = spread
         end if
         if (spread <= noisy_spread) exit
      end do
      if (best_repeats == 0) return ! (no round with a spread: times of zero)
      c%timing_rounds = rounds
      c%repeats = best_repeats
      c%run_time = best_time
      c%run_time_spread = best_spread
   end subroutine time_case

   !> Case order by decreasing estimated cost (particles x steps).
   function by_decreasing_cost(cases) result(order)
      type(sweep_case_t), intent(in) :: cases(:)
      integer, allocatable :: order(:)
      order = sort_order(-case_cost(cases))
   end function by_decreasing_cost

   !> A case's estimated cost in particle-steps (the time loop's work; set-up is negligible).
   elemental real(dp) function case_cost(c)
      type(sweep_case_t), intent(in) :: c
      case_cost = real(c%particles, dp)*real(c%steps, dp)
   end function case_cost

   !> Expected cost of each case in a pass, for the progress estimate. Error pass (`min_time` = 0):
   !> particles x steps. Timing pass: seconds, each completed case being repeated until `min_time`
   !> is measured and at least 3 times, i.e. max(min_time, 3 t) with t = `seconds_per_cost` x
   !> particles x steps (failed cases are not timed: 0).
   pure function case_weights(cases, seconds_per_cost, min_time) result(weights)
      type(sweep_case_t), intent(in) :: cases(:)
      real(dp), intent(in) :: seconds_per_cost, min_time
      real(dp), allocatable :: weights(:)
      if (min_time <= 0.0_dp) then
         weights = case_cost(cases)
      else
         weights = merge(max(min_time, 3.0_dp*seconds_per_cost*case_cost(cases)), 0.0_dp, cases%status == status_ok)
      end if
   end function case_weights

   !> The cases of shard `shard` of `shards` of a sweep of `total` cases (cases shard, shard + shards, ...).
   pure integer function shard_cases(total, shard, shards)
      integer, intent(in) :: total, shard, shards
      shard_cases = (total - shard)/shards + 1
   end function shard_cases

   !> The file this process writes: the namelist's `file`, or its shard's name when the sweep is sharded.
   function sweep_output_file(sweep) result(path)
      type(sweep_t), intent(in) :: sweep
      character(len=:), allocatable :: path
      path = trim(sweep%base%file)
      if (sweep%settings%shards > 1) path = shard_file(path, sweep%settings%shard, sweep%settings%shards)
   end function sweep_output_file

   !> The file of shard `shard` of `shards`: out.h5 -> out_shard002of004.h5 (at least 3 digits, as many
   !> as the shard count has).
   function shard_file(path, shard, shards) result(name)
      character(len=*), intent(in) :: path
      integer, intent(in) :: shard, shards
      character(len=:), allocatable :: name
      character(len=48) :: suffix, form
      integer :: dot, width
      width = max(3, len(str(shards)))
      write (form, '("(""_shard"",i",i0,".",i0,",""of"",i",i0,".",i0,")")') width, width, width, width
      write (suffix, form) shard, shards
      dot = index(path, '.h5', back=.true.)
      if (dot == len(path) - 2 .and. dot > 0) then
         name = path(1:dot - 1)//trim(suffix)//'.h5'
      else
         name = path//trim(suffix)
      end if
   end function shard_file

   !> The &sweep group as namelist text (stored in the output file): every list, then the run
   !> settings, ending with shard and shards (merge compares shards without them).
   function sweep_namelist(settings) result(text)
      type(sweep_config_t), intent(in) :: settings
      character(len=:), allocatable :: text
      type(sweep_config_t), target :: local
      type(parameter_t), allocatable :: table(:)
      integer :: j
      text = '&sweep'
      do j = 1, size(settings%lists)
         text = text//' '//trim(settings%lists(j)%name)//'='//list_text(settings%lists(j))//','
      end do
      local = settings
      call sweep_parameters(local, table)
      do j = 1, size(table)
         text = text//' '//trim(table(j)%name)//'='//format_value(table(j))
         if (j < size(table)) text = text//','
      end do
      text = text//' /'
   end function sweep_namelist
end module mpm_sweep
