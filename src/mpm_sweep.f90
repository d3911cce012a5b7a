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
   use mpm_config, only: config_t, read_config, validate_config, resolve_config, is_known_scheme, known_schemes, &
                         read_group_error, unset, group_text
   use mpm_simulation, only: run_result_t, run_simulation, guard_trip_t, guard_message
   use mpm_diagnostics, only: history_t, status_ok, status_setup_failed, status_not_run
   use mpm_progress, only: progress_t
   use mpm_sort, only: sort_order, median
   implicit none
   private
   public :: sweep_config_t, sweep_case_t, sweep_t, read_sweep, sweep_cases, run_sweep, has_sweep_group, case_config
   public :: max_list

   !> Longest list one &sweep variable accepts.
   integer, parameter :: max_list = 256

   !> The &sweep group: lists to combine and how to run them.
   type :: sweep_config_t
      character(len=8), allocatable :: schemes(:)
      integer, allocatable :: elements(:), particles_per_element(:), modes(:)
      real(dp), allocatable :: dt_fractions(:), youngs_moduli(:), densities(:), velocity_amplitudes(:)
      !> Timing pass: repeat each case until this much run time is measured (s); 0 switches it off.
      real(dp) :: min_time = 0.02_dp
      !> Threads for the error pass (0: OMP_NUM_THREADS or all cores) and for the timing pass.
      integer :: threads = 0
      integer :: timing_threads = 1
      !> Keep per-case histories (u_cm, energies per step) in the sweep file.
      logical :: histories = .false.
      !> This process runs shard `shard` of `shards` (cases shard, shard+shards, ...).
      integer :: shard = 1
      integer :: shards = 1
      !> Show a progress line on standard error (only when it is a terminal).
      logical :: progress = .true.
      character(len=:), allocatable :: namelist_text
   end type sweep_config_t

   !> One case of the sweep and what it produced.
   type :: sweep_case_t
      integer :: index = 0                 !< position in the full (unsharded) table, 1-based
      character(len=8) :: scheme = ''
      integer :: elements = 0, particles_per_element = 0, mode = 1
      real(dp) :: dt_fraction = 0.0_dp, youngs_modulus = 0.0_dp, density = 0.0_dp, velocity_amplitude = 0.0_dp
      integer :: steps = 0, particles = 0, repeats = 0
      integer :: status = status_not_run
      real(dp) :: dt = 0.0_dp, max_error = 0.0_dp, relative_error = 0.0_dp, run_time = 0.0_dp
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

   !> Read the base groups and &sweep from `path`, validate everything, build this shard's cases.
   !> `shard_override`/`shards_override` (> 0) and `threads_override` (>= 0) come from the command line.
   subroutine read_sweep(path, study, error, shard_override, shards_override, threads_override)
      character(len=*), intent(in) :: path
      type(sweep_t), intent(out) :: study
      type(error_t), allocatable, intent(out) :: error
      integer, intent(in) :: shard_override, shards_override, threads_override

      character(len=8) :: schemes(max_list)
      integer :: elements(max_list), particles_per_element(max_list), modes(max_list)
      real(dp) :: dt_fractions(max_list), youngs_moduli(max_list), densities(max_list), velocity_amplitudes(max_list)
      real(dp) :: min_time
      integer :: threads, timing_threads, shard, shards
      logical :: histories, progress
      namelist /sweep/ schemes, elements, particles_per_element, dt_fractions, youngs_moduli, densities, &
         velocity_amplitudes, modes, min_time, threads, timing_threads, histories, shard, shards, progress
      integer, parameter :: none = -huge(1)
      integer :: unit, stat
      character(len=512) :: msg
      type(sweep_config_t) :: defaults

      call read_config(path, study%base, error, extra_groups=['sweep'])
      if (allocated(error)) return

      schemes = ''
      elements = none
      particles_per_element = none
      modes = none
      dt_fractions = unset
      youngs_moduli = unset
      densities = unset
      velocity_amplitudes = unset
      min_time = defaults%min_time
      threads = defaults%threads
      timing_threads = defaults%timing_threads
      histories = defaults%histories
      shard = defaults%shard
      shards = defaults%shards
      progress = defaults%progress
      open (newunit=unit, file=path, status='old', action='read', iostat=stat, iomsg=msg)
      if (stat /= 0) then
         call set_error(error, "cannot open input file '"//trim(path)//"': "//trim(msg))
         return
      end if
      read (unit, nml=sweep, iostat=stat, iomsg=msg)
      close (unit)
      if (stat /= 0) then
         call set_error(error, read_group_error(path, 'sweep', 'schemes, elements, particles_per_element, '// &
            'dt_fractions, youngs_moduli, densities, velocity_amplitudes, modes, min_time, threads, '// &
            'timing_threads, histories, shard, shards, progress', stat, msg))
         return
      end if
      call check_empty_lists(lower(group_text(path, 'sweep')), error)
      if (allocated(error)) return
      if (shards_override > 0) then
         shard = shard_override
         shards = shards_override
      end if
      if (threads_override >= 0) threads = threads_override

      ! Lists left out sweep over the base value of the corresponding variable.
      associate (s => study%settings, b => study%base)
         s%schemes = list_or_default_text(schemes, b%scheme)
         s%elements = list_or_default_int(elements, b%elements)
         s%particles_per_element = list_or_default_int(particles_per_element, b%particles_per_element)
         s%modes = list_or_default_int(modes, b%mode)
         s%dt_fractions = list_or_default_real(dt_fractions, b%dt_fraction)
         s%youngs_moduli = list_or_default_real(youngs_moduli, b%youngs_modulus)
         s%densities = list_or_default_real(densities, b%density)
         s%velocity_amplitudes = list_or_default_real(velocity_amplitudes, b%velocity_amplitude)
         s%min_time = min_time
         s%threads = threads
         s%timing_threads = timing_threads
         s%histories = histories
         s%shard = shard
         s%shards = shards
         s%progress = progress
      end associate
      call validate_sweep(study, error)
      if (allocated(error)) return
      study%settings%namelist_text = sweep_namelist(study%settings)
      call sweep_cases(study, error)
   contains
      !> A list given with a gap (a value after an unset one) is an error; `given` counts values.
      function list_or_default_int(list, base) result(values)
         integer, intent(in) :: list(:), base
         integer, allocatable :: values(:)
         integer :: given
         given = count(list /= none)
         if (any(list(given + 1:) /= none)) call append_error(error, "sweep: a list has a gap; give values contiguously")
         if (given == 0) then
            values = [base]
         else
            values = list(1:given)
         end if
      end function list_or_default_int
      function list_or_default_real(list, base) result(values)
         real(dp), intent(in) :: list(:), base
         real(dp), allocatable :: values(:)
         integer :: given
         given = count(list /= unset)
         if (any(list(given + 1:) /= unset)) call append_error(error, "sweep: a list has a gap; give values contiguously")
         if (given == 0) then
            values = [base]
         else
            values = list(1:given)
         end if
      end function list_or_default_real
      function list_or_default_text(list, base) result(values)
         character(len=*), intent(in) :: list(:), base
         character(len=8), allocatable :: values(:)
         integer :: given
         given = count(list /= '')
         if (given == 0) then
            values = [character(len=8) :: base]
         else
            values = list(1:given)
         end if
      end function list_or_default_text
   end subroutine read_sweep

   !> gfortran accepts `name = /` or `name = , other = ...` and leaves the list untouched; a sweep
   !> over an empty list is surely a mistake, so report it.
   subroutine check_empty_lists(body, error)
      character(len=*), intent(in) :: body
      type(error_t), allocatable, intent(inout) :: error
      integer :: i, j, start
      character(len=*), parameter :: word = 'abcdefghijklmnopqrstuvwxyz0123456789_'
      do i = 1, len_trim(body)
         if (body(i:i) /= '=') cycle
         ! the value: up to the next '/', or the next identifier followed by '='
         j = i + 1
         do while (j <= len_trim(body))
            if (body(j:j) /= ' ' .and. body(j:j) /= ',') exit
            j = j + 1
         end do
         if (j > len_trim(body)) exit
         if (body(j:j) == '/' .or. is_name_assignment(j)) then
            start = i - 1
            do while (start > 1)
               if (body(start:start) /= ' ') exit
               start = start - 1
            end do
            j = start
            do while (j > 1)
               if (scan(body(j - 1:j - 1), word) == 0) exit
               j = j - 1
            end do
            call append_error(error, "sweep: "//body(j:start)//" is an empty list; allowed: one or more values")
         end if
         if (index(body(i:), '/') == 0) exit
      end do
   contains
      logical function is_name_assignment(k)
         integer, intent(in) :: k
         integer :: m
         is_name_assignment = .false.
         m = k
         do while (m <= len_trim(body))
            if (scan(body(m:m), word) == 0) exit
            m = m + 1
         end do
         if (m == k) return
         do while (m <= len_trim(body))
            if (body(m:m) /= ' ') exit
            m = m + 1
         end do
         is_name_assignment = body(m:m) == '='
      end function is_name_assignment
   end subroutine check_empty_lists

   !> Check every list value and the run settings; report all problems.
   subroutine validate_sweep(sweep, error)
      type(sweep_t), intent(inout) :: sweep
      type(error_t), allocatable, intent(inout) :: error
      integer :: i
      associate (s => sweep%settings)
         do i = 1, size(s%schemes)
            if (.not. is_known_scheme(lower(s%schemes(i)))) call append_error(error, "sweep: schemes("//str(i)// &
               ") = '"//trim(s%schemes(i))//"' is unknown; allowed: "//known_schemes)
            s%schemes(i) = lower(s%schemes(i))
         end do
         do i = 1, size(s%elements)
            if (s%elements(i) < 1) call append_error(error, "sweep: elements("//str(i)//") = "//str(s%elements(i))// &
                                                     " is out of range; allowed: integer >= 1")
         end do
         do i = 1, size(s%particles_per_element)
            if (s%particles_per_element(i) < 1) call append_error(error, "sweep: particles_per_element("//str(i)// &
               ") = "//str(s%particles_per_element(i))//" is out of range; allowed: integer >= 1")
         end do
         do i = 1, size(s%modes)
            if (s%modes(i) < 1) call append_error(error, "sweep: modes("//str(i)//") = "//str(s%modes(i))// &
                                                  " is out of range; allowed: integer >= 1")
         end do
         call positive_list(s%dt_fractions, 'dt_fractions')
         call positive_list(s%youngs_moduli, 'youngs_moduli')
         call positive_list(s%densities, 'densities')
         do i = 1, size(s%velocity_amplitudes)
            if (.not. ieee_is_finite(s%velocity_amplitudes(i))) call append_error(error, "sweep: velocity_amplitudes("// &
               str(i)//") is not finite; allowed: finite real (m/s)")
         end do
         if (.not. ieee_is_finite(s%min_time) .or. s%min_time < 0.0_dp .or. s%min_time > 3600.0_dp) &
            call append_error(error, "sweep: min_time = "//str(s%min_time)//" is out of range; allowed: 0 (no timing "// &
                              "pass) to 3600 s")
         if (s%threads < 0) call append_error(error, "sweep: threads = "//str(s%threads)// &
                                              " is out of range; allowed: 0 (all) or a positive integer")
         if (s%timing_threads < 1) call append_error(error, "sweep: timing_threads = "//str(s%timing_threads)// &
                                                     " is out of range; allowed: integer >= 1")
         if (s%shards < 1 .or. s%shard < 1 .or. s%shard > s%shards) call append_error(error, "sweep: shard = "// &
            str(s%shard)//" of shards = "//str(s%shards)//" is out of range; allowed: 1 <= shard <= shards")
         if (product(int([size(s%schemes), size(s%elements), size(s%particles_per_element), size(s%dt_fractions), &
                          size(s%youngs_moduli), size(s%densities), size(s%velocity_amplitudes), size(s%modes)], i8)) &
             > 10000000_i8) call append_error(error, "sweep: the lists give more than 10^7 cases; allowed: at most 10^7")
      end associate
   contains
      subroutine positive_list(list, name)
         real(dp), intent(in) :: list(:)
         character(len=*), intent(in) :: name
         integer :: k
         do k = 1, size(list)
            if (.not. ieee_is_finite(list(k)) .or. list(k) <= 0.0_dp) call append_error(error, "sweep: "//name//"("// &
               str(k)//") = "//str(list(k))//" is out of range; allowed: finite real > 0")
         end do
      end subroutine positive_list
   end subroutine validate_sweep

   !> The configuration of one case: the base with the case's values, resolved.
   function case_config(base, c) result(config)
      type(config_t), intent(in) :: base
      type(sweep_case_t), intent(in) :: c
      type(config_t) :: config
      config = base
      config%scheme = c%scheme
      config%elements = c%elements
      config%particles_per_element = c%particles_per_element
      config%dt_fraction = c%dt_fraction
      config%youngs_modulus = c%youngs_modulus
      config%density = c%density
      config%velocity_amplitude = c%velocity_amplitude
      config%mode = c%mode
      config%snapshot_count = 0
      call resolve_config(config)
   end function case_config

   !> Build this shard's cases (every combination; the last list varies fastest) and validate
   !> each one as a single run would be validated.
   subroutine sweep_cases(sweep, error)
      type(sweep_t), intent(inout) :: sweep
      type(error_t), allocatable, intent(inout) :: error
      integer :: a, b, c, d, e, f, g, h, n, mine
      type(sweep_case_t) :: one
      type(config_t) :: config
      type(error_t), allocatable :: case_error
      associate (s => sweep%settings)
         sweep%total_cases = size(s%schemes)*size(s%elements)*size(s%particles_per_element)*size(s%dt_fractions)* &
                             size(s%youngs_moduli)*size(s%densities)*size(s%velocity_amplitudes)*size(s%modes)
         allocate (sweep%cases((sweep%total_cases - s%shard)/s%shards + 1))
         n = 0
         mine = 0
         do a = 1, size(s%schemes)
         do b = 1, size(s%elements)
         do c = 1, size(s%particles_per_element)
         do d = 1, size(s%dt_fractions)
         do e = 1, size(s%youngs_moduli)
         do f = 1, size(s%densities)
         do g = 1, size(s%velocity_amplitudes)
         do h = 1, size(s%modes)
            n = n + 1
            if (mod(n - 1, s%shards) /= s%shard - 1) cycle
            one = sweep_case_t(index=n, scheme=s%schemes(a), elements=s%elements(b), &
                               particles_per_element=s%particles_per_element(c), dt_fraction=s%dt_fractions(d), &
                               youngs_modulus=s%youngs_moduli(e), density=s%densities(f), &
                               velocity_amplitude=s%velocity_amplitudes(g), mode=s%modes(h))
            config = case_config(sweep%base, one)
            config%history = s%histories
            call validate_config(config, case_error, with_system=.false.)
            if (allocated(case_error)) then
               call append_error(error, "sweep case "//str(n)//" ("//trim(one%scheme)//", "//str(one%elements)// &
                                 " elements, "//str(one%particles_per_element)//" particles per element, dt_fraction "// &
                                 str(one%dt_fraction)//"): "//case_error%message)
               deallocate (case_error)
               if (count_lines(error%message) > 20) return
            end if
            one%steps = config%steps
            one%dt = config%dt
            one%particles = config%elements*config%particles_per_element
            mine = mine + 1
            sweep%cases(mine) = one
         end do
         end do
         end do
         end do
         end do
         end do
         end do
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
         largest = case_config(sweep%base, sweep%cases(i))
         largest%history = sweep%settings%histories
         call validate_config(largest, error)
      end subroutine check_system
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
      call over_cases(sweep, order, threads, timing=.false.)
      call describe_failures(sweep)
      sweep%error_pass_time = omp_get_wtime() - start
      if (sweep%settings%min_time > 0.0_dp) then
         call over_cases(sweep, order, sweep%settings%timing_threads, timing=.true.)
         sweep%timing_pass_time = omp_get_wtime() - start - sweep%error_pass_time
      end if
      sweep%wall_time = omp_get_wtime() - start
   end subroutine run_sweep

   !> Every case once, or (timing) every case repeated until min_time; expensive cases first so
   !> the dynamic schedule ends evenly. Each case writes only its own slot.
   subroutine over_cases(sweep, order, threads, timing)
      type(sweep_t), intent(inout) :: sweep
      integer, intent(in) :: order(:), threads
      logical, intent(in) :: timing
      type(progress_t) :: progress
      integer :: k
      call progress%start(merge('timing pass', 'error pass ', timing), size(order), sweep%settings%progress)
      !$omp parallel do default(none) schedule(dynamic, 1) num_threads(threads) shared(sweep, order, progress, timing)
      do k = 1, size(order)
         if (timing) then
            call time_case(sweep%base, sweep%settings%min_time, sweep%cases(order(k)))
         else
            call run_case(sweep%base, sweep%settings%histories, sweep%cases(order(k)))
         end if
         call progress%advance()
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
               c%message = guard_message(c%status, c%trip, case_config(sweep%base, c))
            end if
         end associate
      end do
   end subroutine describe_failures

   !> Run one case and store its summary (and history, if asked) in its own slot.
   subroutine run_case(base, keep_history, c)
      type(config_t), intent(in) :: base
      logical, intent(in) :: keep_history
      type(sweep_case_t), intent(inout) :: c
      type(config_t) :: config
      type(run_result_t) :: result
      type(error_t), allocatable :: error
      config = case_config(base, c)
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
   subroutine time_case(base, min_time, c)
      type(config_t), intent(in) :: base
      real(dp), intent(in) :: min_time
      type(sweep_case_t), intent(inout) :: c
      integer, parameter :: min_repeats = 3, max_repeats = 100000
      type(config_t) :: config
      type(run_result_t) :: result
      type(error_t), allocatable :: error
      real(dp), allocatable :: times(:)
      real(dp) :: total
      integer :: n
      if (c%status /= status_ok) return
      config = case_config(base, c)
      config%history = .false.
      allocate (times(max_repeats))
      total = 0.0_dp
      n = 0
      do while ((total < min_time .or. n < min_repeats) .and. n < max_repeats)
         call run_simulation(config, result, error, record_history=.false.)
         if (allocated(error)) return
         n = n + 1
         times(n) = result%run_time
         total = total + result%run_time
      end do
      c%repeats = n
      c%run_time = median(times(1:n))
   end subroutine time_case

   !> Case order by decreasing estimated cost (particles x steps).
   function by_decreasing_cost(cases) result(order)
      type(sweep_case_t), intent(in) :: cases(:)
      integer, allocatable :: order(:)
      integer :: i
      order = sort_order([(-real(cases(i)%particles, dp)*cases(i)%steps, i=1, size(cases))])
   end function by_decreasing_cost

   !> The &sweep group as namelist text (stored in the output file).
   function sweep_namelist(s) result(text)
      type(sweep_config_t), intent(in) :: s
      character(len=:), allocatable :: text
      integer :: i
      text = "&sweep schemes="
      do i = 1, size(s%schemes)
         text = text//"'"//trim(s%schemes(i))//"'"//merge(',', ' ', i < size(s%schemes))
      end do
      text = text//"elements="//ints(s%elements)//"particles_per_element="//ints(s%particles_per_element)// &
             "dt_fractions="//reals(s%dt_fractions)//"youngs_moduli="//reals(s%youngs_moduli)// &
             "densities="//reals(s%densities)//"velocity_amplitudes="//reals(s%velocity_amplitudes)// &
             "modes="//ints(s%modes)//"min_time="//str(s%min_time)//", threads="//str(s%threads)// &
             ", timing_threads="//str(s%timing_threads)//", histories="//merge('T', 'F', s%histories)// &
             ", shard="//str(s%shard)//", shards="//str(s%shards)//" /"
   contains
      function ints(list) result(t)
         integer, intent(in) :: list(:)
         character(len=:), allocatable :: t
         integer :: k
         t = ''
         do k = 1, size(list)
            t = t//str(list(k))//', '
         end do
      end function ints
      function reals(list) result(t)
         real(dp), intent(in) :: list(:)
         character(len=:), allocatable :: t
         integer :: k
         t = ''
         do k = 1, size(list)
            t = t//str(list(k))//', '
         end do
      end function reals
   end function sweep_namelist
end module mpm_sweep
