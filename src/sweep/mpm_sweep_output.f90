!> HDF5 output of a sweep (one flat table under /cases, layout in docs/output.md), the merge of
!> shard files into the file an unsharded run gives, and the reading back of a sweep's own file to
!> resume it.
module mpm_sweep_output
   use, intrinsic :: iso_c_binding, only: c_long_long
   use, intrinsic :: iso_fortran_env, only: int8
   use mpm_kinds, only: dp
   use mpm_errors, only: error_t, set_error
   use mpm_strings, only: str
   use mpm_hdf5, only: h5_writer_t, h5_read_real, h5_read_int, h5_read_columns, h5_read_string, h5_read_attribute_string, &
                       h5_read_attribute_int, h5_read_attribute_real, h5_exists
   use mpm_files, only: path_kind, path_regular, path_other
   use mpm_output, only: write_config_attributes
   use mpm_version, only: code_version
   use mpm_diagnostics, only: history_t, status_name, status_ok, status_not_run
   use mpm_sweep, only: sweep_t, sweep_case_t, case_columns, apply_record, record_sweep, record_case
   use mpm_journal, only: journal_record_t, journal_name, journal_read, journal_open, journal_append, journal_close
   use mpm_config, only: config_t, config_parameters, catalog_parameters, config_namelist, used_with, new_config
   use mpm_scenes, only: scene_slot_t
   use mpm_registry, only: parameter_t, value_list_t, single_value_list, type_real, type_int, used_by
   implicit none
   private
   public :: write_sweep_file, merge_sweep_files, resume_sweep, open_sweep_journal, close_sweep_journal

   !> Sweep-level numbers written as /sweep attributes.
   type :: sweep_info_t
      character(len=:), allocatable :: namelist_text
      integer :: total_cases = 0, threads = 0, timing_threads = 0, shard = 1, shards = 1
      real(dp) :: min_time = 0.0_dp, wall_time = 0.0_dp, error_pass_time = 0.0_dp, timing_pass_time = 0.0_dp
   end type sweep_info_t

   !> A merge under way: the table the shards fill, and what the first shard says of the sweep.
   type :: merge_table_t
      type(sweep_info_t) :: info
      character(len=:), allocatable :: config_text
      type(sweep_case_t), allocatable :: cases(:)
      type(value_list_t), allocatable :: columns(:)
      logical, allocatable :: seen(:), filled(:)
   end type merge_table_t

   integer, parameter :: message_length = 1024
   !> Between the parts of a journal's identity record.
   character(len=1), parameter :: separator = achar(0)

contains

   !> Write the sweep's results to `path` (via a .part file), with each case's history when the sweep
   !> keeps them (those of a resumed sweep's earlier cases were read back by resume_sweep).
   subroutine write_sweep_file(path, sweep, error)
      character(len=*), intent(in) :: path
      type(sweep_t), intent(in) :: sweep
      type(error_t), allocatable, intent(out) :: error
      type(h5_writer_t) :: h5
      type(sweep_info_t) :: info
      integer :: i
      ! (component by component: gfortran 12 mis-sizes a deferred-length character in a structure constructor)
      info%namelist_text = sweep%settings%namelist_text
      info%total_cases = sweep%total_cases
      info%threads = sweep%threads_used
      info%timing_threads = sweep%settings%timing_threads
      info%shard = sweep%settings%shard
      info%shards = sweep%settings%shards
      info%min_time = sweep%settings%min_time
      info%wall_time = sweep%wall_time
      info%error_pass_time = sweep%error_pass_time
      info%timing_pass_time = sweep%timing_pass_time
      call h5%create(path)
      call h5%attribute_string('/', 'code_version', code_version)
      call h5%attribute_string('/', 'content', 'sweep')
      call h5%group('/config')
      call write_config_attributes(h5, '/config', sweep%base)
      call write_table(h5, info, sweep%cases, scene_columns(sweep))
      if (sweep%settings%histories) then
         call h5%group('/histories')
         do i = 1, size(sweep%cases)
            call write_history(h5, sweep%cases(i)%index, sweep%cases(i)%history)
         end do
      end if
      call h5%finish(error)
   end subroutine write_sweep_file

   !> The /cases columns of the swept variables the sweep's scene uses (a vibrating bar's sweep has
   !> no gap or gravity column) and some of its laws and integrators use (an explicit sweep has no
   !> newton_tolerance column, a Hencky sweep no yield_stress), one value per case. The laws and
   !> integrators are the base's and those of the sweep's law and integrator lists, the same for every
   !> shard of the sweep.
   function scene_columns(sweep) result(columns)
      type(sweep_t), intent(in) :: sweep
      type(value_list_t), allocatable :: columns(:)
      type(config_t), target :: local
      type(parameter_t), allocatable :: table(:)
      character(len=64), allocatable :: laws(:), integrators(:)
      logical, allocatable :: used(:)
      integer :: j, a, b
      local = sweep%base
      call config_parameters(local, table)
      laws = [character(len=64) :: sweep%base%law]
      integrators = [character(len=64) :: sweep%base%integrator]
      do j = 1, size(sweep%settings%lists)
         associate (list => sweep%settings%lists(j))
            if (table(list%entry)%name == 'law') laws = [laws, list%texts]
            if (table(list%entry)%name == 'integrator') integrators = [integrators, list%texts]
         end associate
      end do
      allocate (used(size(sweep%settings%lists)))
      do j = 1, size(sweep%settings%lists)
         associate (p => table(sweep%settings%lists(j)%entry))
            used(j) = used_by(p, trim(sweep%base%scene_kind)) .and. &
                      any([((used_with(p, trim(laws(a)), trim(integrators(b))), a=1, size(laws)), &
                            b=1, size(integrators))])
         end associate
      end do
      columns = case_columns(sweep, pack([(j, j=1, size(used))], used), sweep%cases)
   end function scene_columns

   !> The history of case `index` as /histories/<index> (nothing when it recorded none).
   subroutine write_history(h5, index, history)
      type(h5_writer_t), intent(inout) :: h5
      integer, intent(in) :: index
      type(history_t), intent(in) :: history
      character(len=:), allocatable :: group
      integer :: n
      n = history%recorded
      if (n == 0) return
      group = '/histories/'//history_name(index)
      call h5%group(group)
      call h5%write_real(group//'/time', history%time(0:n - 1))
      call h5%write_real(group//'/ucm', history%ucm(0:n - 1))
      call h5%write_real(group//'/ucm_exact', history%ucm_exact(0:n - 1))
      call h5%write_real(group//'/kinetic_energy', history%kinetic_energy(0:n - 1))
      call h5%write_real(group//'/strain_energy', history%strain_energy(0:n - 1))
   end subroutine write_history

   !> The history of case `index` in sweep file `path` (recorded 0 when the file has none).
   subroutine read_history(path, index, history, error)
      character(len=*), intent(in) :: path
      integer, intent(in) :: index
      type(history_t), intent(out) :: history
      type(error_t), allocatable, intent(out) :: error
      real(dp), allocatable :: columns(:, :)
      integer :: n
      call h5_read_columns(path, '/histories/'//history_name(index), [character(len=16) :: 'time', 'ucm', &
                           'ucm_exact', 'kinetic_energy', 'strain_energy'], columns, error)
      if (allocated(error)) return
      n = size(columns, 1)
      if (n == 0) return
      history%recorded = n
      ! (indexed from 0, as a run records them)
      allocate (history%time(0:n - 1), history%ucm(0:n - 1), history%ucm_exact(0:n - 1), &
                history%kinetic_energy(0:n - 1), history%strain_energy(0:n - 1))
      history%time(:) = columns(:, 1)
      history%ucm(:) = columns(:, 2)
      history%ucm_exact(:) = columns(:, 3)
      history%kinetic_energy(:) = columns(:, 4)
      history%strain_energy(:) = columns(:, 5)
   end subroutine read_history

   function history_name(index) result(name)
      integer, intent(in) :: index
      character(len=:), allocatable :: name
      character(len=12) :: buffer
      write (buffer, '(i6.6)') index
      name = trim(buffer)
   end function history_name

   !> /sweep attributes and the /cases columns: the index, one column per swept variable of the
   !> scene (`columns`, one value per case), then the results.
   subroutine write_table(h5, info, cases, columns)
      type(h5_writer_t), intent(inout) :: h5
      type(sweep_info_t), intent(in) :: info
      type(sweep_case_t), intent(in) :: cases(:)
      type(value_list_t), intent(in) :: columns(:)
      character(len=:), allocatable :: messages(:)
      character(len=32), allocatable :: names(:)
      integer :: i, longest
      call h5%group('/sweep')
      call h5%attribute_string('/sweep', 'namelist', info%namelist_text)
      call h5%attribute_int('/sweep', 'cases', info%total_cases)
      call h5%attribute_int('/sweep', 'threads', info%threads)
      call h5%attribute_int('/sweep', 'timing_threads', info%timing_threads)
      call h5%attribute_real('/sweep', 'min_time', info%min_time)
      call h5%attribute_real('/sweep', 'wall_time', info%wall_time)
      call h5%attribute_real('/sweep', 'error_pass_time', info%error_pass_time)
      call h5%attribute_real('/sweep', 'timing_pass_time', info%timing_pass_time)
      call h5%attribute_int('/sweep', 'shard', info%shard)
      call h5%attribute_int('/sweep', 'shards', info%shards)

      call h5%group('/cases')
      call h5%write_int('/cases/index', cases%index)
      do i = 1, size(columns)
         call write_column(columns(i))
      end do
      call h5%write_int('/cases/particles', cases%particles)
      call h5%write_int('/cases/steps', cases%steps)
      call h5%write_real('/cases/dt', cases%dt)
      call h5%write_real('/cases/max_error', cases%max_error)
      call h5%write_real('/cases/relative_error', cases%relative_error)
      call h5%write_real('/cases/error_before_stop', cases%error_before_stop)
      call h5%write_real('/cases/relative_error_before_stop', cases%relative_error_before_stop)
      call h5%write_real('/cases/run_time', cases%run_time)
      call h5%write_int('/cases/repeats', cases%repeats)
      call h5%write_real('/cases/run_time_spread', cases%run_time_spread)
      call h5%write_int('/cases/timing_rounds', cases%timing_rounds)
      call h5%write_int('/cases/status', cases%status)
      ! (the messages as long as the longest, at most message_length: a sweep of short messages does not
      ! fill and write message_length characters per case)
      longest = 1
      do i = 1, size(cases)
         longest = max(longest, min(len(case_message(cases(i))), message_length))
      end do
      allocate (names(size(cases)))
      allocate (character(len=longest) :: messages(size(cases)))
      do i = 1, size(cases)
         names(i) = status_name(cases(i)%status)
         messages(i) = case_message(cases(i))
      end do
      call h5%write_strings('/cases/status_name', names)
      call h5%write_strings('/cases/message', messages)
      ! when a guard stopped the case, as numbers (0 where it completed or did not run)
      call h5%write_int('/cases/trip_step', cases%trip%step)
      call h5%write_real('/cases/trip_time', cases%trip%time)
      call h5%write_real('/cases/max_energy_ratio', cases%max_energy_ratio)
      call h5%write_real('/cases/final_energy_ratio', cases%final_energy_ratio)
      call h5%write_real('/cases/min_volume_ratio', cases%min_volume_ratio)
      call h5%write_real('/cases/max_cell_move', cases%max_cell_move)
      call h5%write_real('/cases/min_node_mass_ratio', cases%min_node_mass_ratio)
   contains
      !> The case's /cases/message: as a single run's /summary/message when it completed, what stopped
      !> it otherwise.
      function case_message(c) result(text)
         type(sweep_case_t), intent(in) :: c
         character(len=:), allocatable :: text
         text = ''
         if (allocated(c%message)) text = c%message
         if (c%status == status_ok) text = 'completed'
         if (c%status == status_not_run) text = 'not run: the sweep was interrupted before this '// &
                                                'case finished; no result (mpm1d SWEEP.nml --resume runs it)'
      end function case_message
      subroutine write_column(column)
         type(value_list_t), intent(in) :: column
         character(len=:), allocatable :: texts(:)
         select case (column%type)
         case (type_real)
            call h5%write_real('/cases/'//trim(column%column), column%reals)
         case (type_int)
            call h5%write_int('/cases/'//trim(column%column), column%ints)
         case default
            allocate (character(len=column%width) :: texts(size(column%texts)))
            texts(:) = column%texts
            call h5%write_strings('/cases/'//trim(column%column), texts)
         end select
      end subroutine write_column
   end subroutine write_table

   !> Continue the sweep that wrote `path` (the same input, the same shard) from what it kept: the
   !> sweep file an interrupted run wrote (SIGINT, SIGTERM, SIGHUP) and the journal beside it (a run
   !> killed, or whose output could not be written); each case that ran takes its results from there,
   !> the journal's being the later ones; the others stay not run. A file or journal of another sweep
   !> is refused, naming it and what differs; a file of another sweep beside this sweep's journal is
   !> the one the killed run would have replaced, and is passed over. The journal's torn last record
   !> (a kill in the middle of its write) is dropped (sweep%journal_torn bytes).
   subroutine resume_sweep(path, sweep, error)
      character(len=*), intent(in) :: path
      type(sweep_t), intent(inout) :: sweep
      type(error_t), allocatable, intent(out) :: error
      type(sweep_info_t) :: info
      type(sweep_case_t), allocatable :: cases(:)
      type(journal_record_t), allocatable :: records(:)
      character(len=:), allocatable :: config_text, journal, differs
      integer(c_long_long) :: valid, torn
      logical :: use_file, use_journal
      integer :: i
      journal = journal_name(path)
      use_file = path_kind(path) == path_regular
      use_journal = path_kind(journal) == path_regular
      if (.not. use_file .and. .not. use_journal) then
         call set_error(error, "resume: '"//path//"' does not exist (or is not a file), nor its journal '"// &
                        journal//"': nothing to resume; run the sweep without --resume")
         return
      end if
      if (use_journal) then
         call journal_read(journal, records, valid, torn, error)
         if (allocated(error)) then
            error%message = 'resume: '//error%message
            return
         end if
         sweep%journal_bytes = valid
         sweep%journal_torn = torn
         use_journal = size(records) > 0
         if (use_journal) then
            differs = journal_differs(records(1), sweep)
            if (len(differs) > 0) then
               call set_error(error, "resume: the journal '"//journal//"' holds another sweep: "//differs// &
                              "; allowed: the journal this sweep (the same input and overrides) wrote, or run "// &
                              "without --resume to start afresh")
               return
            end if
         else if (.not. use_file) then
            call set_error(error, "resume: the journal '"//journal//"' holds no whole record (the sweep was "// &
                           "killed as it began it) and '"//path//"' does not exist: nothing to resume; run the "// &
                           "sweep without --resume")
            return
         end if
      end if
      if (use_file) then
         call read_info(path, 'resume', info, config_text, error)
         if (allocated(error)) return
         differs = sweep_differs(sweep, config_text, info)
         if (len(differs) > 0 .and. use_journal) then
            use_file = .false.
         else if (len(differs) > 0) then
            call refuse(differs)
            return
         end if
      end if
      if (use_file) then
         call read_cases(path, 'resume', cases, error)
         if (allocated(error)) return
         if (size(cases) /= size(sweep%cases)) then
            call refuse('it holds '//str(size(cases))//' cases, this shard has '//str(size(sweep%cases)))
            return
         end if
         if (any(cases%index /= sweep%cases%index)) then
            call refuse('its cases are not this shard''s')
            return
         end if
         do i = 1, size(cases)
            if (cases(i)%status == status_not_run) cycle
            if (sweep%settings%histories) then
               call read_history(path, cases(i)%index, cases(i)%history, error)
               if (allocated(error)) then
                  error%message = 'resume: '//error%message
                  return
               end if
            end if
            sweep%cases(i) = cases(i)
         end do
         sweep%wall_time = info%wall_time
         sweep%error_pass_time = info%error_pass_time
         sweep%timing_pass_time = info%timing_pass_time
      end if
      if (.not. use_journal) return
      do i = 2, size(records)
         call apply_record(sweep, records(i), error)
         if (allocated(error)) then
            error%message = "resume: the journal '"//journal//"' holds "//error%message
            return
         end if
         if (records(i)%kind == record_case) sweep%journal_cases = sweep%journal_cases + 1
      end do
      sweep%journal_records = size(records) - 1
   contains
      subroutine refuse(what)
         character(len=*), intent(in) :: what
         call set_error(error, "resume: '"//path//"' holds another sweep: "//what//"; allowed: the file this "// &
                        "sweep (the same input and overrides) wrote, or run without --resume to start afresh")
      end subroutine refuse
   end subroutine resume_sweep

   !> What differs between `sweep` and the sweep whose /config namelist is `config_text` and /sweep
   !> attributes `info` ('' when they are the same sweep: only what changes results is compared).
   function sweep_differs(sweep, config_text, info) result(what)
      type(sweep_t), intent(in) :: sweep
      character(len=*), intent(in) :: config_text
      type(sweep_info_t), intent(in) :: info
      character(len=:), allocatable :: what
      what = ''
      if (config_text /= config_namelist(sweep%base)) then
         what = 'its configuration (/config) differs from this input''s'
      else if (results_part(info%namelist_text) /= results_part(sweep%settings%namelist_text)) then
         what = 'its &sweep group differs from this input''s'
      else if (info%total_cases /= sweep%total_cases) then
         what = 'it has '//str(info%total_cases)//' cases, this sweep '//str(sweep%total_cases)
      else if (info%shard /= sweep%settings%shard .or. info%shards /= sweep%settings%shards) then
         what = 'it is shard '//str(info%shard)//' of '//str(info%shards)//', this run shard '// &
                str(sweep%settings%shard)//' of '//str(sweep%settings%shards)
      end if
   end function sweep_differs

   !> The first record of a sweep's journal: the format and the bytes of a case record's guard trip (a
   !> build whose records differ cannot read them), then the configuration's namelist, the &sweep group,
   !> the cases, the shard and the shards, each ended by a NUL (which no namelist text holds).
   function journal_identity(sweep) result(bytes)
      type(sweep_t), intent(in) :: sweep
      integer(int8), allocatable :: bytes(:)
      character(len=:), allocatable :: text
      text = identity_format()//separator//config_namelist(sweep%base)//separator//sweep%settings%namelist_text// &
             separator//str(sweep%total_cases)//separator//str(sweep%settings%shard)//separator// &
             str(sweep%settings%shards)
      bytes = transfer(text, [0_int8], len(text))
   end function journal_identity

   !> The journal format and this build's layout of a case record.
   function identity_format() result(text)
      character(len=:), allocatable :: text
      type(sweep_case_t) :: c
      text = 'mpm1d sweep journal 1, guard trip of '//str(size(transfer(c%trip, [0_int8])))//' bytes'
   end function identity_format

   !> What differs between `sweep` and the one a journal's first record `record` identifies ('' if none).
   function journal_differs(record, sweep) result(what)
      type(journal_record_t), intent(in) :: record
      type(sweep_t), intent(in) :: sweep
      character(len=:), allocatable :: what, text
      character(len=:), allocatable :: lines(:)
      type(sweep_info_t) :: info
      integer :: stat(3)
      what = 'its first record is not a sweep''s identity'
      if (record%kind /= record_sweep) return
      allocate (character(len=size(record%payload)) :: text)
      text = transfer(record%payload, text)
      lines = split_text(text)
      if (size(lines) /= 6) return
      if (trim(lines(1)) /= identity_format()) then
         what = "it was written by another build of mpm1d ('"//trim(lines(1))//"'; this one: '"//identity_format()//"')"
         return
      end if
      info%namelist_text = trim(lines(3))
      read (lines(4), *, iostat=stat(1)) info%total_cases
      read (lines(5), *, iostat=stat(2)) info%shard
      read (lines(6), *, iostat=stat(3)) info%shards
      if (any(stat /= 0)) return
      what = sweep_differs(sweep, trim(lines(2)), info)
   end function journal_differs

   !> The parts of `text` between separators (each as long as the longest).
   function split_text(text) result(parts)
      character(len=*), intent(in) :: text
      character(len=:), allocatable :: parts(:)
      integer :: count, start, i, k, longest
      count = 1
      longest = 0
      start = 1
      do i = 1, len(text)
         if (text(i:i) /= separator) cycle
         count = count + 1
         longest = max(longest, i - start)
         start = i + 1
      end do
      longest = max(longest, len(text) + 1 - start)
      allocate (character(len=longest) :: parts(count))
      k = 1
      start = 1
      do i = 1, len(text)
         if (text(i:i) /= separator) cycle
         parts(k) = text(start:i - 1)
         k = k + 1
         start = i + 1
      end do
      parts(k) = text(start:)
   end function split_text

   !> Open this sweep's journal beside its output `path`: a resumed sweep appends to the journal it read
   !> (its torn last record cut off), any other starts it empty with its identity. A journal another
   !> process holds (a sweep into the same output running now) is refused to a resumed sweep (`error`);
   !> a fresh sweep then runs without one, as it does when the journal cannot be made: `warning` says so,
   !> or that the journal of an earlier sweep that did not finish was replaced.
   subroutine open_sweep_journal(path, sweep, resumed, warning, error)
      character(len=*), intent(in) :: path
      type(sweep_t), intent(inout) :: sweep
      logical, intent(in) :: resumed
      character(len=:), allocatable, intent(out) :: warning
      type(error_t), allocatable, intent(out) :: error
      type(error_t), allocatable :: problem
      character(len=:), allocatable :: journal
      integer(c_long_long) :: keep
      logical :: in_use
      warning = ''
      journal = journal_name(path)
      keep = 0
      if (resumed) keep = sweep%journal_bytes
      call journal_open(sweep%journal, journal, keep, in_use, problem)
      if (in_use) then
         if (resumed) then
            call set_error(error, "resume: another mpm1d process is running this sweep now (it holds the "// &
                           "journal '"//journal//"'); allowed: --resume once it has ended")
         else
            warning = "another mpm1d process is running a sweep into '"//path//"' now (it holds the journal '"// &
                      journal//"'): this sweep keeps no journal, and a kill would lose its finished cases"
         end if
         return
      end if
      if (allocated(problem)) then
         warning = problem%message//": this sweep keeps no journal, and a kill would lose its finished cases"
         return
      end if
      if (keep == 0) then
         if (sweep%journal%found > 0) warning = "the journal '"//journal//"' of an earlier sweep into '"//path// &
                                                "' that did not finish was replaced (--resume would have continued it)"
         call journal_append(sweep%journal, record_sweep, journal_identity(sweep))
      end if
   end subroutine open_sweep_journal

   !> Close the sweep's journal: removed once `written` (the output holds every case it held), kept
   !> otherwise (a --resume reads it).
   subroutine close_sweep_journal(sweep, written)
      type(sweep_t), intent(inout) :: sweep
      logical, intent(in) :: written
      call journal_close(sweep%journal, remove=written)
   end subroutine close_sweep_journal

   !> Join shard files (every shard 1..n of one sweep, each once) into `path`: the same table,
   !> in the same case order, as one unsharded run; run times and pass times are the shards'.
   !> `output_failed` tells a failure to write `path` (exit 3) from a problem of the inputs (exit 2).
   !> Shards may differ in their threads and timing settings (results do not depend on them).
   !> Each shard's cases go straight to their place in the table (linear time in the shards).
   subroutine merge_sweep_files(path, inputs, error, output_failed)
      character(len=*), intent(in) :: path
      character(len=*), intent(in) :: inputs(:)
      type(error_t), allocatable, intent(out) :: error
      logical, intent(out), optional :: output_failed
      type(merge_table_t) :: table
      integer :: i
      if (present(output_failed)) output_failed = .false.
      if (size(inputs) < 1) then
         call set_error(error, 'merge: give the output file and at least one shard file')
         return
      end if
      ! as a single run refuses it: writing would replace a named pipe or device with a regular file
      if (path_kind(path) == path_other) then
         call set_error(error, "merge: output file '"//trim(path)//"' is not a regular file (a device, FIFO or "// &
                        "socket); allowed: a new file or a regular file to replace")
         return
      end if
      do i = 1, size(inputs)
         call add_shard(table, trim(inputs(i)), trim(inputs(1)), error)
         if (allocated(error)) return
      end do
      call check_complete(table, error)
      if (allocated(error)) return
      call write_merged(path, inputs, table, error)
      if (present(output_failed)) output_failed = allocated(error)
   end subroutine merge_sweep_files

   !> Read one shard into the table: the first one sets up the table, each other must be a
   !> shard of the same sweep, not seen before, whose cases go to places not yet filled.
   subroutine add_shard(table, input, first, error)
      type(merge_table_t), intent(inout) :: table
      character(len=*), intent(in) :: input, first
      type(error_t), allocatable, intent(out) :: error
      type(sweep_info_t) :: info
      type(sweep_case_t), allocatable :: part(:)
      type(value_list_t), allocatable :: part_columns(:)
      character(len=:), allocatable :: text
      integer, allocatable :: where(:)
      integer :: j, k
      call read_info(input, 'merge', info, text, error)
      if (allocated(error)) return
      if (.not. allocated(table%seen)) then
         call start_table(table, info, text, input)
      else if (info%shards /= table%info%shards .or. text /= table%config_text .or. &
               info%total_cases /= table%info%total_cases .or. &
               results_part(info%namelist_text) /= results_part(table%info%namelist_text)) then
         call set_error(error, "merge: '"//input//"' is not a shard of the same sweep as '"//first//"'")
         return
      else
         table%info%wall_time = table%info%wall_time + info%wall_time
         table%info%error_pass_time = table%info%error_pass_time + info%error_pass_time
         table%info%timing_pass_time = table%info%timing_pass_time + info%timing_pass_time
      end if
      if (table%seen(info%shard)) then
         call set_error(error, "merge: shard "//str(info%shard)//" is given twice ('"//input//"')")
         return
      end if
      table%seen(info%shard) = .true.
      call read_cases(input, 'merge', part, error)
      if (allocated(error)) return
      where = part%index
      if (any(where < 1 .or. where > size(table%cases))) then
         call set_error(error, "merge: '"//input//"' holds a case index outside 1 to "//str(size(table%cases)))
         return
      end if
      do j = 1, size(where)
         if (table%filled(where(j))) then
            call set_error(error, "merge: case "//str(where(j))//" is in two shards ('"//input//"')")
            return
         end if
         table%filled(where(j)) = .true.
         table%cases(where(j)) = part(j)
      end do
      part_columns = table%columns
      call read_columns(input, size(part), part_columns, error)
      if (allocated(error)) return
      do k = 1, size(table%columns)
         table%columns(k)%reals(where) = part_columns(k)%reals
         table%columns(k)%ints(where) = part_columns(k)%ints
         table%columns(k)%texts(where) = part_columns(k)%texts
      end do
   end subroutine add_shard

   !> The empty table of the sweep the first shard belongs to: its cases, and the columns of the
   !> swept variables that shard carries (those of its scene).
   subroutine start_table(table, info, config_text, input)
      type(merge_table_t), intent(inout) :: table
      type(sweep_info_t), intent(in) :: info
      character(len=*), intent(in) :: config_text, input
      type(value_list_t), allocatable :: all(:)
      integer :: k, n
      table%info = info
      table%config_text = config_text
      n = info%total_cases
      allocate (table%seen(info%shards), table%cases(n), table%filled(n))
      table%seen = .false.
      table%filled = .false.
      all = sweep_columns()
      allocate (table%columns(0))
      do k = 1, size(all)
         if (h5_exists(input, '/cases/'//trim(all(k)%column))) table%columns = [table%columns, all(k)]
      end do
      do k = 1, size(table%columns)
         table%columns(k)%reals = spread(0.0_dp, 1, n)
         table%columns(k)%ints = spread(0, 1, n)
         table%columns(k)%texts = spread(repeat(' ', 64), 1, n)
      end do
   end subroutine start_table

   !> Every shard given and every case filled.
   subroutine check_complete(table, error)
      type(merge_table_t), intent(in) :: table
      type(error_t), allocatable, intent(out) :: error
      character(len=:), allocatable :: list
      integer :: j
      if (.not. all(table%seen)) then
         list = ''
         do j = 1, size(table%seen)
            if (.not. table%seen(j)) list = list//' '//str(j)
         end do
         call set_error(error, "merge: shards missing: "//list//" of "//str(table%info%shards))
      else if (.not. all(table%filled)) then
         call set_error(error, "merge: the shards hold "//str(count(table%filled))//" cases, the sweep has "// &
                        str(table%info%total_cases))
      end if
   end subroutine check_complete

   !> Write the merged table as an unsharded sweep (shard 1 of 1), with the shards' histories.
   subroutine write_merged(path, inputs, table, error)
      character(len=*), intent(in) :: path
      character(len=*), intent(in) :: inputs(:)
      type(merge_table_t), intent(inout) :: table
      type(error_t), allocatable, intent(out) :: error
      type(sweep_info_t) :: info
      type(h5_writer_t) :: h5
      type(history_t) :: history
      character(len=:), allocatable :: text
      logical :: histories
      integer :: i, k
      table%info%shard = 1
      table%info%shards = 1
      table%info%namelist_text = without_shard(table%info%namelist_text)//", shard=1, shards=1 /"
      histories = .false.
      do i = 1, size(inputs)
         if (h5_exists(trim(inputs(i)), '/histories')) histories = .true.
      end do
      call h5%create(path)
      call h5%attribute_string('/', 'code_version', code_version)
      call h5%attribute_string('/', 'content', 'sweep')
      call h5%group('/config')
      call h5%copy_attributes(trim(inputs(1)), '/config')
      call write_table(h5, table%info, table%cases, table%columns)
      if (histories) then
         call h5%group('/histories')
         do i = 1, size(inputs)
            ! a shard holds the histories of its own cases: shard, shard + shards, ...
            call read_info(trim(inputs(i)), 'merge', info, text, error)
            if (allocated(error)) then
               call h5%abandon()
               return
            end if
            do k = info%shard, size(table%cases), info%shards
               call read_history(trim(inputs(i)), k, history, error)
               if (allocated(error)) then
                  error%message = 'merge: '//error%message
                  call h5%abandon()
                  return
               end if
               call write_history(h5, k, history)
            end do
         end do
      end if
      call h5%finish(error)
   end subroutine write_merged

   !> The sweep namelist text without what does not change results: the shard, the threads and the
   !> timing pass (min_time, timing_threads) and the progress line.
   function results_part(text) result(base)
      character(len=*), intent(in) :: text
      character(len=:), allocatable :: base
      character(len=16), parameter :: keys(*) = [character(len=16) :: ' min_time=', ' threads=', &
                                                  ' timing_threads=', ' progress=']
      integer :: k, start, comma
      base = without_shard(text)
      do k = 1, size(keys)
         start = index(base, trim(keys(k)))
         if (start == 0) cycle
         comma = index(base(start + 1:), ',')
         if (comma == 0) then
            base = base(1:start - 1)
         else
            base = base(1:start - 1)//base(start + comma:)
         end if
      end do
   end function results_part

   !> The sweep namelist text without its trailing "shard=.., shards=.. /".
   function without_shard(text) result(base)
      character(len=*), intent(in) :: text
      character(len=:), allocatable :: base
      integer :: k
      k = index(text, ', shard=', back=.true.)
      if (k == 0) then
         base = text
      else
         base = text(1:k - 1)
      end if
   end function without_shard

   !> The /sweep attributes and /config namelist of sweep file `path`; `role` ('merge', 'resume')
   !> starts the messages.
   subroutine read_info(path, role, info, config_text, error)
      character(len=*), intent(in) :: path, role
      type(sweep_info_t), intent(out) :: info
      character(len=:), allocatable, intent(out) :: config_text
      type(error_t), allocatable, intent(out) :: error
      character(len=65536) :: buffer
      call h5_read_attribute_string(path, '/', 'content', buffer, error)
      if (allocated(error)) return
      if (trim(buffer) /= 'sweep') then
         call set_error(error, role//": '"//path//"' is not an mpm1d sweep file (content: '"//trim(buffer)//"')")
         return
      end if
      call h5_read_attribute_string(path, '/config', 'namelist', buffer, error)
      if (allocated(error)) return
      config_text = trim(buffer)
      call h5_read_attribute_string(path, '/sweep', 'namelist', buffer, error)
      if (allocated(error)) return
      info%namelist_text = trim(buffer)
      call h5_read_attribute_int(path, '/sweep', 'cases', info%total_cases, error)
      if (.not. allocated(error)) call h5_read_attribute_int(path, '/sweep', 'threads', info%threads, error)
      if (.not. allocated(error)) call h5_read_attribute_int(path, '/sweep', 'timing_threads', info%timing_threads, error)
      if (.not. allocated(error)) call h5_read_attribute_int(path, '/sweep', 'shard', info%shard, error)
      if (.not. allocated(error)) call h5_read_attribute_int(path, '/sweep', 'shards', info%shards, error)
      if (.not. allocated(error)) call h5_read_attribute_real(path, '/sweep', 'min_time', info%min_time, error)
      if (.not. allocated(error)) call h5_read_attribute_real(path, '/sweep', 'wall_time', info%wall_time, error)
      if (.not. allocated(error)) call h5_read_attribute_real(path, '/sweep', 'error_pass_time', info%error_pass_time, error)
      if (.not. allocated(error)) call h5_read_attribute_real(path, '/sweep', 'timing_pass_time', &
                                                              info%timing_pass_time, error)
      if (.not. allocated(error) .and. (info%shard < 1 .or. info%shard > info%shards)) &
         call set_error(error, role//": '"//path//"' has an invalid shard number")
   end subroutine read_info

   !> Read the /cases table of a sweep file back into cases (`role` starts the messages).
   subroutine read_cases(path, role, cases, error)
      character(len=*), intent(in) :: path, role
      type(sweep_case_t), allocatable, intent(out) :: cases(:)
      type(error_t), allocatable, intent(out) :: error
      integer, allocatable :: ints(:)
      real(dp), allocatable :: reals(:)
      character(len=message_length), allocatable :: messages(:)
      integer :: n, i
      call h5_read_int(path, '/cases/index', ints, error)
      if (allocated(error)) return
      n = size(ints)
      allocate (cases(n))
      cases%index = ints
      call int_column('particles')
      cases%particles = ints
      call int_column('steps')
      cases%steps = ints
      call int_column('repeats')
      cases%repeats = ints
      call int_column('timing_rounds')
      cases%timing_rounds = ints
      call real_column('run_time_spread')
      cases%run_time_spread = reals
      call int_column('status')
      cases%status = ints
      call real_column('dt')
      cases%dt = reals
      call real_column('max_error')
      cases%max_error = reals
      call real_column('relative_error')
      cases%relative_error = reals
      call real_column('error_before_stop')
      cases%error_before_stop = reals
      call real_column('relative_error_before_stop')
      cases%relative_error_before_stop = reals
      call real_column('run_time')
      cases%run_time = reals
      call real_column('max_energy_ratio')
      cases%max_energy_ratio = reals
      call real_column('final_energy_ratio')
      cases%final_energy_ratio = reals
      call real_column('min_volume_ratio')
      cases%min_volume_ratio = reals
      call real_column('max_cell_move')
      cases%max_cell_move = reals
      call real_column('min_node_mass_ratio')
      cases%min_node_mass_ratio = reals
      call int_column('trip_step')
      cases%trip%step = ints
      call real_column('trip_time')
      cases%trip%time = reals
      if (allocated(error)) return
      call h5_read_string(path, '/cases/message', message_length, messages, error)
      if (allocated(error)) return
      do i = 1, n
         if (len_trim(messages(i)) > 0) cases(i)%message = trim(messages(i))
      end do
   contains
      subroutine int_column(name)
         character(len=*), intent(in) :: name
         if (allocated(error)) return
         call h5_read_int(path, '/cases/'//name, ints, error)
         if (.not. allocated(error) .and. size(ints) /= n) call set_error(error, role//": column '"//name// &
                                                                          "' of '"//path//"' has the wrong length")
         if (allocated(error)) ints = [(0, i=1, n)]
      end subroutine int_column
      subroutine real_column(name)
         character(len=*), intent(in) :: name
         if (allocated(error)) return
         call h5_read_real(path, '/cases/'//name, reals, error)
         if (.not. allocated(error) .and. size(reals) /= n) call set_error(error, role//": column '"//name// &
                                                                           "' of '"//path//"' has the wrong length")
         if (allocated(error)) reals = [(0.0_dp, i=1, n)]
      end subroutine real_column
   end subroutine read_cases

   !> Empty columns for the sweepable variables of the registry (every scene kind's): name, type and text
   !> width.
   function sweep_columns() result(columns)
      type(value_list_t), allocatable :: columns(:)
      type(config_t), target :: defaults
      type(scene_slot_t), allocatable, target :: slots(:)
      type(parameter_t), allocatable :: table(:)
      integer :: k
      defaults = new_config()
      call catalog_parameters(defaults, slots, table)
      allocate (columns(0))
      do k = 1, size(table)
         if (len_trim(table(k)%sweep_list) == 0) cycle
         columns = [columns, single_value_list(table(k), trim(table(k)%sweep_list))]
      end do
      do k = 1, size(columns)
         deallocate (columns(k)%reals, columns(k)%ints, columns(k)%texts)
         allocate (columns(k)%reals(0), columns(k)%ints(0), columns(k)%texts(0))
      end do
   end function sweep_columns

   !> Read the registry's columns of /cases (`n` cases) of a sweep file; all three value arrays of a
   !> column get `n` entries (those of other types zero or blank).
   subroutine read_columns(path, n, columns, error)
      character(len=*), intent(in) :: path
      integer, intent(in) :: n
      type(value_list_t), intent(inout) :: columns(:)
      type(error_t), allocatable, intent(out) :: error
      character(len=:), allocatable :: name
      integer :: k
      do k = 1, size(columns)
         name = '/cases/'//trim(columns(k)%column)
         columns(k)%reals = spread(0.0_dp, 1, n)
         columns(k)%ints = spread(0, 1, n)
         columns(k)%texts = spread(repeat(' ', 64), 1, n)
         select case (columns(k)%type)
         case (type_real)
            call h5_read_real(path, name, columns(k)%reals, error)
         case (type_int)
            call h5_read_int(path, name, columns(k)%ints, error)
         case default
            block
               character(len=columns(k)%width), allocatable :: texts(:)
               call h5_read_string(path, name, columns(k)%width, texts, error)
               if (.not. allocated(error)) columns(k)%texts = texts
            end block
         end select
         if (allocated(error)) return
         if (size(columns(k)%reals) /= n .or. size(columns(k)%ints) /= n .or. size(columns(k)%texts) /= n) then
            call set_error(error, "merge: column '"//trim(columns(k)%column)//"' of '"//path//"' has the wrong length")
            return
         end if
      end do
   end subroutine read_columns


end module mpm_sweep_output
