!> Parameter sweeps: the &sweep namelist group, the table of cases (every combination of the
!> lists), and running them in parallel with OpenMP (one case per thread at a time, dynamic
!> schedule). Each case writes only its own slot, so results do not depend on the thread count.
!> An error pass runs every case once; an optional timing pass repeats each case until a minimum
!> measured time is reached and keeps the median time per run.
module mpm_sweep
   use, intrinsic :: ieee_arithmetic, only: ieee_is_finite
   use omp_lib, only: omp_get_wtime, omp_get_max_threads
   use mpm_kinds, only: dp, i8
   use mpm_errors, only: error_t, set_error, append_error
   use mpm_strings, only: str, lower
   use mpm_config, only: config_t, read_config_text, input_name, validate_config, resolve_config, &
                         config_parameters, config_groups, not_used_message, known_kind
   use mpm_registry, only: parameter_t, nml_item_t, value_list_t, real_entry, int_entry, logical_entry, &
                           parse_namelist, read_input_text, add_overrides, item_place, read_value_list, &
                           single_value_list, set_from_list, set_parameter, &
                           check_parameter, find_parameter, entry_names, format_value, list_text, quoted, &
                           type_real, type_int, used_by, sweep_name_hint
   use mpm_simulation, only: run_result_t, run_simulation, guard_trip_t, guard_message
   use mpm_diagnostics, only: history_t, status_ok, status_setup_failed, status_not_run
   use mpm_progress, only: progress_t
   use mpm_sort, only: sort_order, median, relative_spread
   implicit none
   private
   public :: sweep_config_t, sweep_case_t, sweep_t, read_sweep, read_sweep_text, sweep_cases, run_sweep
   public :: has_sweep_group, has_sweep_text, case_config, max_threads

   !> Timing pass: a round of repeats whose middle half spans more than this fraction of its median
   !> was disturbed (another process, frequency changes) and is measured again, up to max_rounds
   !> rounds; the round with the smallest spread is kept, and its spread stored for the reader.
   real(dp), parameter :: noisy_spread = 0.2_dp
   integer, parameter :: max_rounds = 3

   !> Most threads a sweep asks for (OpenMP runtimes fail far below 10^5 threads; no node has more cores).
   integer, parameter :: max_threads = 4096
   public :: sweep_parameters, case_column, case_weights

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

   !> One case of the sweep and what it produced.
   type :: sweep_case_t
      !> Position in the full (unsharded) table, 1-based; it gives the value of every list.
      integer :: index = 0
      integer :: steps = 0, particles = 0, repeats = 0
      integer :: status = status_not_run
      real(dp) :: dt = 0.0_dp, max_error = 0.0_dp, relative_error = 0.0_dp, run_time = 0.0_dp
      !> Timing pass: relative spread (interquartile range / median) of the kept round of repeats,
      !> and the rounds measured (a round whose spread exceeds noisy_spread is measured again).
      real(dp) :: run_time_spread = 0.0_dp
      integer :: timing_rounds = 0
      real(dp) :: max_energy_ratio = 0.0_dp, final_energy_ratio = 0.0_dp
      real(dp) :: min_volume_ratio = 0.0_dp, max_cell_move = 0.0_dp, min_node_mass_ratio = 0.0_dp
      character(len=:), allocatable :: message !< why the case failed (made after the parallel loop)
      type(guard_trip_t) :: trip
      type(history_t) :: history
   end type sweep_case_t

   !> A sweep: the base configuration, the &sweep group, this shard's cases and the timings.
   type :: sweep_t
      type(config_t) :: base
      type(sweep_config_t) :: settings
      type(sweep_case_t), allocatable :: cases(:)
      integer :: total_cases = 0
      integer :: threads_used = 0
      real(dp) :: error_pass_time = 0.0_dp, timing_pass_time = 0.0_dp, wall_time = 0.0_dp
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
         logical_entry('sweep', 'progress', settings%progress, 'a progress line on standard error (a terminal only)'), &
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
            if (known_kind(study%base%scene_kind) .and. .not. used_by(base(k), trim(study%base%scene_kind))) then
               call append_error(error, where//"sweep: list '"//items(i)%name//"' varies "// &
                                 not_used_message(base(k), study%base%scene_kind))
               cycle
            end if
            call read_value_list(base(k), items(i)%name, items(i)%values, where, study%settings%lists(j), error)
            study%settings%lists(j)%entry = k
            study%settings%lists(j)%name = base(k)%sweep_list  ! the list's name, whichever name was given
            cycle
         end if
         k = find_parameter(settings, 'sweep', items(i)%name)
         if (k == 0) then
            call append_error(error, where//"group &sweep: unknown variable '"//items(i)%name//"'"// &
                              sweep_name_hint(items(i)%name, list_names()//", "//entry_names(settings, 'sweep'), base))
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

   !> Value number of list `j` in case `index` (mixed radix over the lists, the last fastest).
   pure integer function list_position(lists, j, index)
      type(value_list_t), intent(in) :: lists(:)
      integer, intent(in) :: j, index
      integer(i8) :: stride
      integer :: m
      stride = 1
      do m = j + 1, size(lists)
         stride = stride*lists(m)%size()
      end do
      list_position = int(mod((index - 1)/stride, int(lists(j)%size(), i8))) + 1
   end function list_position

   !> The configuration of one case: the base with the case's value of every list, resolved.
   function case_config(sweep, c) result(config)
      type(sweep_t), intent(in) :: sweep
      type(sweep_case_t), intent(in) :: c
      type(config_t) :: config
      type(config_t), target :: local
      type(parameter_t), allocatable :: table(:)
      integer :: j
      local = sweep%base
      call config_parameters(local, table)
      do j = 1, size(sweep%settings%lists)
         associate (list => sweep%settings%lists(j))
            call set_from_list(table(list%entry), list, list_position(sweep%settings%lists, j, c%index))
         end associate
      end do
      local%snapshot_count = 0
      call resolve_config(local)
      config = local
   end function case_config

   !> List `j`'s values over `cases` (a /cases column).
   function case_column(sweep, j, cases) result(column)
      type(sweep_t), intent(in) :: sweep
      integer, intent(in) :: j
      type(sweep_case_t), intent(in) :: cases(:)
      type(value_list_t) :: column
      integer, allocatable :: at(:)
      integer :: i
      associate (list => sweep%settings%lists(j))
         at = [(list_position(sweep%settings%lists, j, cases(i)%index), i=1, size(cases))]
         column = list
         column%reals = list%reals(at)
         column%ints = list%ints(at)
         column%texts = list%texts(at)
      end associate
   end function case_column

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
         allocate (sweep%cases((sweep%total_cases - s%shard)/s%shards + 1))
         mine = 0
         do n = s%shard, sweep%total_cases, s%shards
            one = sweep_case_t(index=n)
            config = case_config(sweep, one)
            config%history = s%histories
            call validate_config(config, case_error, with_system=.false.)
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

   !> Run the error pass (every case once, in parallel) and, when min_time > 0, the timing pass.
   subroutine run_sweep(sweep)
      type(sweep_t), intent(inout) :: sweep
      integer, allocatable :: order(:)
      integer :: threads
      real(dp) :: start

      start = omp_get_wtime()
      threads = sweep%settings%threads
      if (threads == 0) threads = omp_get_max_threads()
      sweep%threads_used = threads
      order = by_decreasing_cost(sweep%cases)
      call over_cases(sweep, order, threads, case_weights(sweep%cases, 0.0_dp, 0.0_dp), timing=.false.)
      call describe_failures(sweep)
      sweep%error_pass_time = omp_get_wtime() - start
      if (sweep%settings%min_time > 0.0_dp) then
         ! the error pass gives the seconds per particle-step on this machine (thread-seconds / cost)
         call over_cases(sweep, order, sweep%settings%timing_threads, case_weights(sweep%cases, &
                         sweep%error_pass_time*threads/max(1.0_dp, sum(cost(sweep%cases))), &
                         sweep%settings%min_time), timing=.true.)
         sweep%timing_pass_time = omp_get_wtime() - start - sweep%error_pass_time
      end if
      sweep%wall_time = omp_get_wtime() - start
   end subroutine run_sweep

   !> Every case once, or (timing) every case repeated until min_time; expensive cases first so
   !> the dynamic schedule ends evenly. Each case writes only its own slot.
   subroutine over_cases(sweep, order, threads, weights, timing)
      type(sweep_t), intent(inout) :: sweep
      integer, intent(in) :: order(:), threads
      real(dp), intent(in) :: weights(:)
      logical, intent(in) :: timing
      type(progress_t) :: progress
      type(config_t) :: config
      integer :: k
      call progress%start(merge('timing pass', 'error pass ', timing), weights(order), sweep%settings%progress)
      !$omp parallel do default(none) schedule(dynamic, 1) num_threads(threads) &
      !$omp shared(sweep, order, progress, timing, weights) &
      !$omp private(config)
      do k = 1, size(order)
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
         call progress%advance(weights(order(k)))
      end do
      !$omp end parallel do
      call progress%finish()
   end subroutine over_cases

   !> Messages of the failed cases, made here, serially (see guard_message).
   subroutine describe_failures(sweep)
      type(sweep_t), intent(inout) :: sweep
      integer :: i
      do i = 1, size(sweep%cases)
         associate (c => sweep%cases(i))
            if (c%status == status_setup_failed) then
               c%message = 'the run could not be set up: not enough memory for '//str(c%particles)//' particles'
            else if (c%status /= status_ok) then
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
      c%status = result%status
      c%trip = result%trip
      c%max_error = result%max_error
      c%relative_error = result%relative_error
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
   !> reached (at least 3 runs) and keep the median time per run. Failed cases are not timed.
   subroutine time_case(case, min_time, c)
      type(config_t), intent(in) :: case
      real(dp), intent(in) :: min_time
      type(sweep_case_t), intent(inout) :: c
      integer, parameter :: min_repeats = 3, max_repeats = 100000
      type(config_t) :: config
      type(run_result_t) :: result
      type(error_t), allocatable :: error
      real(dp), allocatable :: times(:)
      real(dp) :: total, spread
      integer :: n, round
      if (c%status /= status_ok) return
      config = case
      config%history = .false.
      allocate (times(max_repeats))
      c%run_time_spread = huge(1.0_dp)
      do round = 1, max_rounds
         total = 0.0_dp
         n = 0
         do while ((total < min_time .or. n < min_repeats) .and. n < max_repeats)
            call run_simulation(config, result, error, record_history=.false.)
            if (allocated(error)) return
            n = n + 1
            times(n) = result%run_time
            total = total + result%run_time
         end do
         spread = relative_spread(times(1:n))
         c%timing_rounds = round
         if (spread < c%run_time_spread) then
            c%repeats = n
            c%run_time = median(times(1:n))
            c%run_time_spread = spread
         end if
         if (spread <= noisy_spread) exit
      end do
   end subroutine time_case

   !> Case order by decreasing estimated cost (particles x steps).
   function by_decreasing_cost(cases) result(order)
      type(sweep_case_t), intent(in) :: cases(:)
      integer, allocatable :: order(:)
      order = sort_order(-cost(cases))
   end function by_decreasing_cost

   !> A case's estimated cost in particle-steps (the time loop's work; set-up is negligible).
   elemental real(dp) function cost(c)
      type(sweep_case_t), intent(in) :: c
      cost = real(c%particles, dp)*real(c%steps, dp)
   end function cost

   !> Expected cost of each case in a pass, for the progress estimate. Error pass (`min_time` = 0):
   !> particles x steps. Timing pass: seconds, each completed case being repeated until `min_time`
   !> is measured and at least 3 times, i.e. max(min_time, 3 t) with t = `seconds_per_cost` x
   !> particles x steps (failed cases are not timed: 0).
   pure function case_weights(cases, seconds_per_cost, min_time) result(weights)
      type(sweep_case_t), intent(in) :: cases(:)
      real(dp), intent(in) :: seconds_per_cost, min_time
      real(dp), allocatable :: weights(:)
      if (min_time <= 0.0_dp) then
         weights = cost(cases)
      else
         weights = merge(max(min_time, 3.0_dp*seconds_per_cost*cost(cases)), 0.0_dp, cases%status == status_ok)
      end if
   end function case_weights

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
