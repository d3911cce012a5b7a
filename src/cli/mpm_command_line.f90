!> mpm1d's command line read into what to do: `mpm1d [input.nml | -] [group.name=value ...] [--quiet]
!> [--shard I/N] [--threads N] [--resume] [--restart] [--dry-run]`, `mpm1d merge OUT SHARD...`, `mpm1d --help | --list-parameters |
!> --version`; and the checks of the input that come before the namelist's (OMP_NUM_THREADS, an input
!> without any group). Every refusal names the argument and what is allowed; an argument `name=value`
!> without its group is told the group (`elements=40`: discretisation.elements=40).
module mpm_command_line
   use mpm_errors, only: error_t, set_error
   use mpm_strings, only: str, lower
   use mpm_suggest, only: nearest_words, printable
   use mpm_registry, only: parameter_t, parse_namelist, nml_item_t
   use mpm_config, only: config_t, catalog_parameters, new_config
   use mpm_scenes, only: scene_slot_t
   use mpm_sweep, only: sweep_config_t, sweep_parameters, max_threads
   implicit none
   private
   public :: argument_t, command_line_t, command_arguments, parse_command_line, check_environment
   public :: check_has_groups, override_length

   !> Longest override accepted (the length of command_line_t's overrides).
   integer, parameter :: override_length = 1024
   character(len=*), parameter :: see_help = '; see mpm1d --help'
   !> whole_number's verdicts besides 0.
   integer, parameter :: not_a_number = 1, beyond_integers = 2

   !> One command-line argument, as typed.
   type :: argument_t
      character(len=:), allocatable :: text
   end type argument_t

   !> What the command line asks for.
   type :: command_line_t
      !> 'run' (a single run or a sweep), 'help', 'list-parameters', 'version' or 'merge'.
      character(len=16) :: action = 'run'
      !> The input file ('-': standard input); has_input false: the built-in case.
      character(len=:), allocatable :: input
      logical :: has_input = .false.
      character(len=override_length), allocatable :: overrides(:)
      logical :: quiet = .false.
      !> With --resume, run only the cases the sweep's output file has as not_run; with --dry-run, say
      !> what would run (cases, output path) and run nothing.
      logical :: resume = .false., dry_run = .false.
      !> With --restart, a single run continues from its checkpoint (&output checkpoint_steps).
      logical :: restart = .false.
      !> --shard I/N (0, 0: not given) and --threads N (-1: not given).
      integer :: shard = 0, shards = 0, threads = -1
      !> merge: the output, then the shard files.
      character(len=1024), allocatable :: merge_files(:)
   end type command_line_t

contains

   !> The program's arguments.
   function command_arguments() result(args)
      type(argument_t), allocatable :: args(:)
      integer :: i, length
      allocate (args(command_argument_count()))
      do i = 1, size(args)
         call get_command_argument(i, length=length)
         allocate (character(len=length) :: args(i)%text)
         call get_command_argument(i, args(i)%text)
      end do
   end function command_arguments

   !> Read `args` into `cl`; a problem gives `error` (a usage error: exit 2).
   subroutine parse_command_line(args, cl, error)
      type(argument_t), intent(in) :: args(:)
      type(command_line_t), intent(out) :: cl
      type(error_t), allocatable, intent(out) :: error
      integer :: i
      allocate (cl%overrides(0), cl%merge_files(0))
      if (size(args) >= 1) then
         select case (args(1)%text)
         case ('-h', '--help', '--list-parameters', '-V', '--version')
            if (size(args) > 1) then
               call set_error(error, "'"//args(1)%text//"' takes no other arguments (given: '"// &
                              printable(args(2)%text)//"')"//see_help)
               return
            end if
            select case (args(1)%text)
            case ('-h', '--help')
               cl%action = 'help'
            case ('-V', '--version')
               cl%action = 'version'
            case default
               cl%action = 'list-parameters'
            end select
            return
         case ('merge')
            call read_merge(args, cl, error)
            return
         end select
      end if
      i = 1
      do while (i <= size(args))
         call read_argument(args, i, cl, error)
         if (allocated(error)) return
         i = i + 1
      end do
   end subroutine parse_command_line

   !> Argument `i` of a run (an option with its value moves `i` past the value).
   subroutine read_argument(args, i, cl, error)
      type(argument_t), intent(in) :: args(:)
      integer, intent(inout) :: i
      type(command_line_t), intent(inout) :: cl
      type(error_t), allocatable, intent(inout) :: error
      character(len=:), allocatable :: option
      option = args(i)%text
      select case (option)
      case ('-q', '--quiet')
         cl%quiet = .true.
      case ('--resume')
         cl%resume = .true.
      case ('--restart')
         cl%restart = .true.
      case ('--dry-run')
         cl%dry_run = .true.
      case ('--shard=':'--shard=~')
         call read_shard(option(9:), cl, error)
      case ('--threads=':'--threads=~')
         call read_threads(option(11:), cl, error)
      case ('--shard', '--threads')
         if (i == size(args)) then
            call set_error(error, "option '"//option//"' needs a value"//see_help)
            return
         end if
         i = i + 1
         if (option == '--shard') then
            call read_shard(args(i)%text, cl, error)
         else
            call read_threads(args(i)%text, cl, error)
         end if
      case ('-')
         if (cl%has_input) then
            call set_error(error, "too many input files: '"//cl%input//"' and '-'"//see_help)
            return
         end if
         cl%input = option
         cl%has_input = .true.
      case default
         call read_operand(option, i, cl, error)
      end select
   end subroutine read_argument

   !> An argument that is no option: an override `group.name=value`, or the input file.
   subroutine read_operand(text, i, cl, error)
      character(len=*), intent(in) :: text
      integer, intent(in) :: i
      type(command_line_t), intent(inout) :: cl
      type(error_t), allocatable, intent(inout) :: error
      if (len(text) == 0) then
         call set_error(error, 'argument '//str(i)//' is an empty argument; allowed: an input file, an override '// &
                        'group.name=value or an option (see mpm1d --help)')
      else if (text(1:1) == '-') then
         call set_error(error, "unknown option '"//printable(text)//"'"//see_help)
      else if (is_override(text) .and. (cl%has_input .or. .not. exists(text))) then
         if (len(text) > override_length) then
            call set_error(error, "override '"//printable(text(1:60))//"...' is too long; allowed: "// &
                           str(override_length)//" characters")
            return
         end if
         cl%overrides = [character(len=override_length) :: cl%overrides, text]
      else if (is_assignment(text) .and. .not. exists(text)) then
         ! `elements=40`: an override without its group
         if (cl%has_input) then
            call set_error(error, "too many arguments: '"//printable(text)//"' after the input file '"// &
                           printable(cl%input)//"' ("//group_hint(text)//")")
         else
            call set_error(error, "argument '"//printable(text)//"' is neither a file nor an override; "// &
                           group_hint(text))
         end if
      else if (.not. cl%has_input) then
         cl%input = text
         cl%has_input = .true.
      else
         call set_error(error, "too many arguments: '"//printable(text)//"' after the input file '"// &
                        printable(cl%input)//"'; usage: mpm1d [input.nml | -] [group.name=value ...] (see mpm1d --help)")
      end if
   end subroutine read_operand

   !> What an assignment `name=value` without a group should have been: the group of `name` in the
   !> registry (a run's variable, then a sweep setting or list), or the nearest name there.
   function group_hint(text) result(hint)
      character(len=*), intent(in) :: text
      character(len=:), allocatable :: hint, name, value, names, near
      type(config_t), target :: config
      type(scene_slot_t), allocatable, target :: slots(:)
      type(sweep_config_t), target :: settings
      type(parameter_t), allocatable :: table(:), sweep_table(:)
      integer :: k, eq
      eq = index(text, '=')
      name = lower(text(1:eq - 1))
      value = text(eq:)
      config = new_config()
      call catalog_parameters(config, slots, table)
      call sweep_parameters(settings, sweep_table)
      table = [table, sweep_table]
      names = ''
      do k = 1, size(table)
         ! a list of several values for a sweepable variable: its &sweep list
         if (index(value, ',') > 0 .and. (name == trim(table(k)%sweep_list) .or. (len_trim(table(k)%sweep_alias) > 0 &
             .and. name == trim(table(k)%sweep_alias)))) then
            hint = "an override names its group: sweep."//name//printable(value)//" (a sweep over these values)"
            return
         end if
      end do
      do k = 1, size(table)
         if (trim(table(k)%name) == name) then
            hint = "an override names its group: "//trim(table(k)%group)//"."//name//printable(value)
            return
         end if
         if (len(names) > 0) names = names//','
         names = names//trim(table(k)%name)
      end do
      near = nearest_words(name, names)
      if (index(near, ',') > 0) near = near(1:index(near, ',') - 1)
      hint = "allowed: an input file, or an override group.name=value (e.g. discretisation.elements=40)"
      do k = 1, size(table)
         if (len(near) == 0) exit
         if (trim(table(k)%name) /= near) cycle
         hint = "did you mean the override "//trim(table(k)%group)//"."//near//printable(value)//"?"
         exit
      end do
   end function group_hint

   !> `--shard I/N`: whole numbers with 1 <= I <= N.
   subroutine read_shard(text, cl, error)
      character(len=*), intent(in) :: text
      type(command_line_t), intent(inout) :: cl
      type(error_t), allocatable, intent(inout) :: error
      integer :: slash, stat_i, stat_n
      character(len=*), parameter :: allowed = '; allowed: I/N, whole numbers with 1 <= I <= N'
      slash = index(text, '/')
      if (slash < 2 .or. slash == len(text)) then
         call set_error(error, "--shard "//printable(text)//" is malformed"//allowed)
         return
      end if
      call whole_number(text(1:slash - 1), cl%shard, stat_i)
      call whole_number(text(slash + 1:), cl%shards, stat_n)
      if (stat_i == not_a_number .or. stat_n == not_a_number) then
         call set_error(error, "--shard "//printable(text)//" is malformed"//allowed)
      else if (stat_i /= 0 .or. stat_n /= 0) then
         call set_error(error, "--shard "//printable(text)//" is out of range: beyond the integers"//allowed)
      else if (cl%shard < 1) then
         call set_error(error, "--shard "//text//" is out of range: I = "//str(cl%shard)//" must be >= 1"//allowed)
      else if (cl%shards < 1) then
         call set_error(error, "--shard "//text//" is out of range: N = "//str(cl%shards)//" must be >= 1"//allowed)
      else if (cl%shard > cl%shards) then
         call set_error(error, "--shard "//text//" is out of range: I = "//str(cl%shard)//" must be <= N = "// &
                        str(cl%shards)//allowed)
      end if
   end subroutine read_shard

   !> `--threads N`: 0 (all cores) to max_threads.
   subroutine read_threads(text, cl, error)
      character(len=*), intent(in) :: text
      type(command_line_t), intent(inout) :: cl
      type(error_t), allocatable, intent(inout) :: error
      integer :: stat
      character(len=:), allocatable :: allowed
      allowed = '; allowed: 0 (all cores) to '//str(max_threads)
      call whole_number(text, cl%threads, stat)
      if (stat == not_a_number) then
         call set_error(error, "--threads '"//printable(text)//"' is not a whole number"//allowed)
      else if (stat /= 0 .or. cl%threads < 0 .or. cl%threads > max_threads) then
         call set_error(error, '--threads '//printable(text)//' is out of range'//allowed)
      end if
   end subroutine read_threads

   !> `text` as a whole number with an optional sign: stat 0, or not_a_number, or beyond_integers.
   subroutine whole_number(text, value, stat)
      character(len=*), intent(in) :: text
      integer, intent(out) :: value, stat
      character(len=:), allocatable :: digits
      integer :: read_stat
      value = 0
      stat = not_a_number
      digits = trim(adjustl(text))
      if (len(digits) == 0) return
      if (digits(1:1) == '+' .or. digits(1:1) == '-') then
         if (len(digits) == 1) return
         if (verify(digits(2:), '0123456789') /= 0) return
      else if (verify(digits, '0123456789') /= 0) then
         return
      end if
      stat = beyond_integers
      if (len(digits) > 11) return
      read (digits, *, iostat=read_stat) value
      if (read_stat /= 0) return
      stat = 0
   end subroutine whole_number

   !> `mpm1d merge OUT.h5 SHARD.h5 ...`: an output and at least one shard, none of them empty.
   subroutine read_merge(args, cl, error)
      type(argument_t), intent(in) :: args(:)
      type(command_line_t), intent(inout) :: cl
      type(error_t), allocatable, intent(inout) :: error
      character(len=*), parameter :: usage = 'usage: mpm1d merge OUT.h5 SHARD1.h5 [SHARD2.h5 ...]'
      integer :: i
      cl%action = 'merge'
      if (size(args) < 3) then
         call set_error(error, usage)
         return
      end if
      do i = 2, size(args)
         if (len(args(i)%text) == 0) then
            call set_error(error, 'merge: argument '//str(i)//' is an empty argument; '//usage)
            return
         end if
         if (len(args(i)%text) > len(cl%merge_files)) then
            call set_error(error, "merge: argument "//str(i)//" is longer than "//str(len(cl%merge_files))// &
                           " characters")
            return
         end if
      end do
      cl%merge_files = [character(len=len(cl%merge_files)) :: (args(i)%text, i=2, size(args))]
   end subroutine read_merge

   !> Is `text` an override `group.name=value`?
   logical function is_override(text)
      character(len=*), intent(in) :: text
      integer :: eq, dot
      eq = index(text, '=')
      is_override = .false.
      if (eq < 4) return
      dot = index(text(1:eq - 1), '.')
      if (dot < 2 .or. dot > eq - 2) return
      is_override = verify(text(1:eq - 1), 'abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789_.') == 0
   end function is_override

   !> Is `text` an assignment `name=value` (a name without a group)?
   logical function is_assignment(text)
      character(len=*), intent(in) :: text
      integer :: eq
      eq = index(text, '=')
      is_assignment = .false.
      if (eq < 2) return
      is_assignment = verify(text(1:eq - 1), 'abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789_') == 0 &
                      .and. verify(text(1:1), 'abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ') == 0
   end function is_assignment

   logical function exists(path)
      character(len=*), intent(in) :: path
      inquire (file=path, exist=exists)
   end function exists

   !> OMP_NUM_THREADS, which a sweep's threads = 0 follows: whole numbers 1 to max_threads (a list
   !> "4,2" for nested levels); libgomp only warns about other text and crashes on 100000 threads.
   subroutine check_environment(error)
      type(error_t), allocatable, intent(out) :: error
      character(len=:), allocatable :: value, item
      integer :: length, comma, n, stat
      call get_environment_variable('OMP_NUM_THREADS', length=length)
      if (length == 0) return
      allocate (character(len=length) :: value)
      call get_environment_variable('OMP_NUM_THREADS', value)
      value = trim(adjustl(value))
      if (len(value) == 0) return
      do
         comma = index(value, ',')
         item = trim(adjustl(value(1:merge(comma - 1, len(value), comma > 0))))
         n = -1
         stat = 1
         if (len(item) > 0 .and. len(item) <= 9 .and. verify(item, '0123456789') == 0) read (item, *, iostat=stat) n
         if (stat /= 0 .or. n < 1 .or. n > max_threads) then
            call set_error(error, "environment: OMP_NUM_THREADS = '"//printable(value)//"' is not a thread count; "// &
                           "allowed: whole numbers 1 to "//str(max_threads)//" (comma-separated for nested levels), "// &
                           "or leave it unset")
            return
         end if
         if (comma == 0) exit
         value = value(comma + 1:)
      end do
   end subroutine check_environment

   !> An input with no namelist group at all (empty, blanks or comments only, and every text the reader
   !> does not refuse line by line) is refused: the built-in case runs only without an input file.
   !> Problems of syntax are left to the reader's full report.
   subroutine check_has_groups(text, source, error)
      character(len=*), intent(in) :: text, source
      type(error_t), allocatable, intent(out) :: error
      type(nml_item_t), allocatable :: items(:)
      character(len=32), allocatable :: groups(:)
      integer, allocatable :: lines(:)
      type(error_t), allocatable :: problem
      call parse_namelist(text, source, items, groups, lines, problem)
      if (allocated(problem)) return
      if (size(groups) == 0) call set_error(error, source//': no namelist group (the input is empty or holds '// &
         'only blanks and comments); allowed: &group name=value, ... / groups (see mpm1d --help); run mpm1d '// &
         'without an input file for the built-in verification case')
   end subroutine check_has_groups
end module mpm_command_line
