!> Checkpoints of a single run: its whole state (mpm_state) every `checkpoint_steps` steps and when a
!> signal stops it, in `<output>.checkpoint`, read back by `mpm1d RUN.nml --restart`. A checkpoint is
!> written under a temporary name, made durable (fsync) and renamed over the older one: a kill at any
!> moment leaves the older checkpoint or the new one, whole. Its format is a journal's (mpm_journal:
!> records framed with a checksum): a first record naming the run (the format, the build's layout, the
!> configuration's variables), one record per value of the state, an end record with the step. A
!> record torn or changed, a missing end, the checkpoint of another input are refused by name.
module mpm_checkpoint
   use, intrinsic :: iso_c_binding, only: c_long_long
   use, intrinsic :: iso_fortran_env, only: int8
   use mpm_errors, only: error_t, set_error
   use mpm_strings, only: str
   use mpm_files, only: sibling_name, process_id, rename_file, remove_file, path_kind, path_regular, path_none, &
                        register_partial, forget_partial, wait_for_signal
   use mpm_journal, only: journal_t, journal_record_t, journal_open, journal_append, journal_close, journal_read
   use mpm_state, only: state_t, state_item_t
   use mpm_config, only: config_t, config_parameters
   use mpm_registry, only: parameter_t, format_value
   use mpm_simulation, only: checkpoint_sink_t
   implicit none
   private
   public :: checkpoint_file_t, checkpoint_name, checkpoint_for, read_checkpoint

   !> The records of a checkpoint: its identity, a value of the state, the end (the step).
   integer, parameter :: record_identity = 1, record_item = 2, record_end = 3
   !> The format, and with it the layout of the values (a build that lays them out otherwise cannot read them).
   character(len=*), parameter :: format_name = 'mpm1d checkpoint 1'

   !> The checkpoints of one run: written to `path`; `failure` says why the last write failed (the run
   !> goes on; the older checkpoint, if any, stays); `step` the step of the last one written.
   type, extends(checkpoint_sink_t) :: checkpoint_file_t
      character(len=:), allocatable :: path, identity
      character(len=:), allocatable :: failure
      integer :: step = -1, written = 0
   contains
      procedure :: save => checkpoint_save
   end type checkpoint_file_t

contains

   !> The checkpoint of output file `path`: `path`.checkpoint (its last part shortened to 255 characters).
   function checkpoint_name(path) result(name)
      character(len=*), intent(in) :: path
      character(len=:), allocatable :: name
      name = sibling_name(path, '.checkpoint')
   end function checkpoint_name

   !> The checkpoints of the run `config` describes (every config%checkpoint_steps steps).
   function checkpoint_for(config) result(file)
      type(config_t), intent(in) :: config
      type(checkpoint_file_t) :: file
      file%every = config%checkpoint_steps
      file%path = checkpoint_name(trim(config%file))
      file%identity = identity(config)
   end function checkpoint_for

   !> The first record's text: the format, the build's layout of a real and an integer, then each
   !> variable of the configuration as `group.name = value`, a line each (all but checkpoint_steps, which
   !> a restarted run may change).
   function identity(config) result(text)
      type(config_t), intent(in) :: config
      character(len=:), allocatable :: text
      type(config_t), target :: local
      type(parameter_t), allocatable :: table(:)
      integer :: i
      text = format_name//', reals of '//str(storage_size(0.0d0)/8)//' bytes, integers of '// &
             str(storage_size(0)/8)
      local = config
      call config_parameters(local, table)
      do i = 1, size(table)
         if (trim(table(i)%name) == 'checkpoint_steps') cycle
         text = text//new_line('a')//trim(table(i)%group)//'.'//trim(table(i)%name)//' = '//format_value(table(i))
      end do
   end function identity

   !> Write `state` (after step `step`) as the checkpoint: a temporary file, made durable, then renamed.
   subroutine checkpoint_save(self, state, step)
      class(checkpoint_file_t), intent(inout) :: self
      type(state_t), intent(in) :: state
      integer, intent(in) :: step
      type(journal_t) :: journal
      type(error_t), allocatable :: error
      character(len=:), allocatable :: part
      logical :: in_use, renamed
      integer :: i
      if (allocated(self%failure)) deallocate (self%failure)
      part = sibling_name(self%path, '.'//str(process_id())//'.part')
      call register_partial(part)
      call journal_open(journal, part, 0_c_long_long, in_use, error)
      if (allocated(error) .or. in_use) then
         self%failure = "cannot write the checkpoint '"//self%path//"'"
         if (allocated(error)) self%failure = error%message
         call forget_partial()
         return
      end if
      call journal_append(journal, record_identity, bytes_of(self%identity))
      do i = 1, state%count
         call journal_append(journal, record_item, state%encode(state%items(i)))
      end do
      call journal_append(journal, record_end, transfer(step, [0_int8]))
      if (allocated(journal%failure)) then
         self%failure = "cannot write the checkpoint '"//self%path//"': "//journal%failure
         call journal_close(journal, remove=.true.)
         call forget_partial()
         return
      end if
      call journal_close(journal, remove=.false.)
      call rename_file(part, self%path, renamed)
      call forget_partial()
      if (.not. renamed) then
         call remove_file(part)
         self%failure = "cannot write the checkpoint '"//self%path//"': the rename of '"//part//"' failed"
         return
      end if
      self%step = step
      self%written = self%written + 1
      if (self%written == pause_hook()) call wait_for_signal(600, 'mpm1d_paused')
   end subroutine checkpoint_save

   !> Test hook: MPM1D_PAUSE_AFTER_CHECKPOINT=N makes the run create the file mpm1d_paused in the
   !> working folder once its N-th checkpoint is written and wait there for a signal (at most 600 s), so
   !> that a test kills or signals it at a known step. 0 when unset or not a number.
   integer function pause_hook()
      character(len=16) :: text
      integer :: length, stat
      pause_hook = 0
      call get_environment_variable('MPM1D_PAUSE_AFTER_CHECKPOINT', text, length=length)
      if (length == 0) return
      read (text, *, iostat=stat) pause_hook
      if (stat /= 0) pause_hook = 0
   end function pause_hook

   !> Read the checkpoint of the run `config` describes into `state`; `error` when there is none, when
   !> it is torn or changed, or when it is another input's (naming the variables that differ).
   subroutine read_checkpoint(config, state, step, error)
      type(config_t), intent(in) :: config
      type(state_t), intent(out) :: state
      integer, intent(out) :: step
      type(error_t), allocatable, intent(out) :: error
      type(journal_record_t), allocatable :: records(:)
      type(state_item_t) :: item
      character(len=:), allocatable :: path, text, differs
      integer(c_long_long) :: valid, torn
      logical :: ok
      integer :: i
      step = -1
      path = checkpoint_name(trim(config%file))
      if (path_kind(path) == path_none) then
         call set_error(error, "restart: there is no checkpoint '"//path//"' (a run writes one every "// &
                        "checkpoint_steps steps of &output, and when a signal stops it); run without --restart")
         return
      else if (path_kind(path) /= path_regular) then
         call set_error(error, "restart: the checkpoint '"//path//"' is not a file")
         return
      end if
      call journal_read(path, records, valid, torn, error)
      if (allocated(error)) then
         error%message = 'restart: '//error%message
         return
      end if
      if (size(records) == 0) then
         call corrupt('no whole first record')
         return
      end if
      if (records(1)%kind /= record_identity) then
         call corrupt('its first record is not a checkpoint''s')
         return
      end if
      allocate (character(len=size(records(1)%payload)) :: text)
      if (len(text) > 0) text = transfer(records(1)%payload, text)
      differs = difference(text, identity(config))
      if (len(differs) > 0) then
         call set_error(error, "restart: the checkpoint '"//path//"' is of another input: "//differs// &
                        "; allowed: --restart with the input (and overrides) of the run that wrote it, or run "// &
                        "without --restart to start afresh")
         return
      end if
      do i = 2, size(records)
         select case (records(i)%kind)
         case (record_item)
            call state%decode(records(i)%payload, item, ok)
            if (.not. ok) then
               call corrupt('its record '//str(i)//' is not a value')
               return
            end if
            call state%add(item)
         case (record_end)
            if (size(records(i)%payload) /= storage_size(step)/8 .or. i /= size(records)) then
               call corrupt('its end record is malformed')
               return
            end if
            step = transfer(records(i)%payload, step)
         case default
            call corrupt('its record '//str(i)//' is of an unknown kind')
            return
         end select
      end do
      if (step < 0) call corrupt('it ends before its end record ('//str(int(torn))//' bytes after the last whole '// &
                                 'record: torn or changed)')
   contains
      subroutine corrupt(what)
         character(len=*), intent(in) :: what
         call set_error(error, "restart: the checkpoint '"//path//"' is damaged: "//what//"; allowed: an undamaged "// &
                        "checkpoint, or run without --restart to start afresh")
      end subroutine corrupt
   end subroutine read_checkpoint

   !> What differs between the identity `found` and this run's `wanted` ('' if nothing): the format, or
   !> the variables whose values differ (by name).
   function difference(found, wanted) result(what)
      character(len=*), intent(in) :: found, wanted
      character(len=:), allocatable :: what, names
      integer :: a, b
      what = ''
      if (found == wanted) return
      a = index(found, new_line('a'))
      b = index(wanted, new_line('a'))
      if (a == 0) then
         what = 'it is not a checkpoint of mpm1d'
         return
      else if (found(:a) /= wanted(:b)) then
         what = "it was written by another build ('"//found(:a - 1)//"'; this one: '"//wanted(:b - 1)//"')"
         return
      end if
      names = differing_names(found(a + 1:), wanted(b + 1:))
      if (len(names) > 0) then
         what = 'these variables differ: '//names
      else
         what = 'its configuration differs'
      end if
   end function difference

   !> The names of the `name = value` lines that differ between two identities (comma-separated).
   function differing_names(a, b) result(names)
      character(len=*), intent(in) :: a, b
      character(len=:), allocatable :: names
      names = ''
      call compare(a, b)
      call compare(b, a)
   contains
      !> Add the variables of `x` whose line is not in `y`.
      subroutine compare(x, y)
         character(len=*), intent(in) :: x, y
         integer :: start, finish, equals
         character(len=:), allocatable :: line, name
         start = 1
         do while (start <= len(x))
            finish = index(x(start:), new_line('a'))
            if (finish == 0) then
               finish = len(x) + 1
            else
               finish = start + finish - 1
            end if
            line = x(start:finish - 1)
            start = finish + 1
            equals = index(line, ' = ')
            if (equals == 0) cycle
            if (index(new_line('a')//y//new_line('a'), new_line('a')//line//new_line('a')) > 0) cycle
            name = trim(adjustl(line(:equals - 1)))
            if (index(' '//names//',', ' '//name//',') > 0) cycle
            if (len(names) > 0) names = names//', '
            names = names//name
         end do
      end subroutine compare
   end function differing_names

   function bytes_of(text) result(bytes)
      character(len=*), intent(in) :: text
      integer(int8), allocatable :: bytes(:)
      bytes = transfer(text, [0_int8], len(text))
   end function bytes_of
end module mpm_checkpoint
