!> The parameter registry: one table entry per input variable (group, name, type, allowed range,
!> unit, help line, sweep list name, /config attribute name) bound by pointer to the field it fills,
!> and everything that works from such a table: a namelist reader of its own (line numbers,
!> quoted strings, logicals, repeat counts, comments, multi-line groups), setting a variable from
!> the text of its values (the same path will serve command-line overrides `group.name=value`),
!> range checks that name group, variable, value and range, and the text of the echo, of --help
!> and of the machine-readable listing the Python loader reads.
!>
!> A table is built on one instance of the type it describes (`config_parameters` in mpm_config,
!> `sweep_parameters` in mpm_sweep) and lives only as long as that instance stays in place.
module mpm_registry
   use, intrinsic :: ieee_arithmetic, only: ieee_is_finite
   use mpm_kinds, only: dp, i8
   use mpm_errors, only: error_t, set_error, append_error
   use mpm_strings, only: str, lower
   implicit none
   private
   public :: parameter_t, nml_value_t, nml_item_t
   public :: real_entry, int_entry, text_entry, logical_entry, real_list_entry
   public :: type_real, type_int, type_text, type_logical, type_real_list, type_name
   public :: read_namelist, parse_namelist, read_input_text, add_overrides, item_place
   public :: apply_items, set_parameter, check_parameter, allowed_text
   public :: value_list_t, read_value_list, single_value_list, set_from_list, list_text
   public :: format_value, quoted, real_value, int_value, text_value, find_parameter, group_namelist
   public :: parameter_listing, parameter_help, short_number, entry_names, used_by, for_kinds

   integer, parameter :: type_real = 1, type_int = 2, type_text = 3, type_logical = 4, type_real_list = 5
   character(len=*), parameter :: identifier_characters = &
                                  'abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789_'

   !> One input variable: what it is, what it may be, and where its value lives.
   type :: parameter_t
      character(len=16) :: group = ''
      character(len=32) :: name = ''
      !> Name of its /config attribute and /cases column (usually `name`).
      character(len=32) :: attribute = ''
      integer :: type = type_real
      character(len=16) :: unit = ''
      character(len=160) :: help = ''
      !> Range of numbers (and of each list element): bounds, whether each is present and open.
      real(dp) :: lower = 0.0_dp, upper = 0.0_dp
      logical :: has_lower = .false., has_upper = .false., lower_open = .false., upper_open = .false.
      !> Allowed words of a text variable, comma separated ('' = any non-empty text that fits).
      character(len=96) :: words = ''
      !> Said after the range in messages and --help (e.g. the meaning of a special value).
      character(len=96) :: note = ''
      !> Name of the &sweep list that varies this variable ('' = not sweepable). One rule: a list is
      !> named as the variable it varies (elements, scheme, dt_fraction, ...).
      character(len=32) :: sweep_list = ''
      !> The list's former name, still accepted in &sweep ('' = none; e.g. schemes, dt_fractions).
      character(len=32) :: sweep_alias = ''
      !> May be left unset (no default: left out of the echo and of /config).
      logical :: optional = .false.
      !> The scene kinds that use it, comma separated ('' = every kind): given for another kind it is
      !> refused, and it is left out of that kind's echo and /config (see used_by).
      character(len=96) :: kinds = ''
      !> Line of the input where it was given (0 = not given).
      integer :: line = 0
      !> Where it was given, as messages name it ("file:line: " or "command line 'group.name=value': ");
      !> fixed length: gfortran 12 corrupts array constructors of this type with an allocatable string.
      character(len=256) :: origin = ''
      real(dp), pointer :: real_value => null()
      integer, pointer :: int_value => null()
      logical, pointer :: logical_value => null()
      character(len=:), pointer :: text_value => null()
      real(dp), pointer :: list_value(:) => null()
      integer, pointer :: list_count => null()
      !> Set when the variable is given (input or command line): an optional variable's "given" is its own
      !> flag, not a value a user could type.
      logical, pointer :: given => null()
   end type parameter_t

   !> One value as written in the input.
   type :: nml_value_t
      character(len=:), allocatable :: text
      logical :: quoted = .false.
      logical :: null = .false.
   end type nml_value_t

   !> One assignment `name = value, value, ...` of group `group` at line `line`.
   type :: nml_item_t
      character(len=:), allocatable :: group, name
      integer :: line = 0
      !> Set for a command-line override: how messages name it ("command line '...': ").
      character(len=:), allocatable :: origin
      type(nml_value_t), allocatable :: values(:)
   end type nml_item_t

   !> The values of one &sweep list, typed as the variable it varies.
   type :: value_list_t
      character(len=32) :: name = ''
      !> Its former name, accepted in &sweep as well ('' = none).
      character(len=32) :: alias = ''
      !> The variable it varies: its index in the table, its /cases column and its text width.
      integer :: entry = 0
      character(len=32) :: column = ''
      integer :: width = 0
      integer :: type = type_real
      real(dp), allocatable :: reals(:)
      integer, allocatable :: ints(:)
      character(len=64), allocatable :: texts(:)
   contains
      procedure :: size => list_size
   end type value_list_t

contains

   ! ------------------------------------------------------------------ table entries

   !> A table entry. `sweep_list` present makes the variable sweepable: its list is named `name`
   !> (the one rule), and `sweep_list`, when it differs, is accepted as an alias (the former name).
   function base_entry(group, name, type, unit, help, attribute, sweep_list, optional, note) result(p)
      character(len=*), intent(in) :: group, name, unit, help
      integer, intent(in) :: type
      character(len=*), intent(in), optional :: attribute, sweep_list, note
      logical, intent(in), optional :: optional
      type(parameter_t) :: p
      p%group = group
      p%name = name
      p%attribute = name
      if (present(attribute)) p%attribute = attribute
      p%type = type
      p%unit = unit
      p%help = help
      if (present(sweep_list)) then
         p%sweep_list = name
         if (sweep_list /= name) p%sweep_alias = sweep_list
      end if
      if (present(optional)) p%optional = optional
      if (present(note)) p%note = note
   end function base_entry

   !> A real variable; `greater_than`/`at_least` and `below`/`at_most` give its range (always finite).
   !> `given` (with `optional`): the flag saying whether the variable has a value (set when it is given).
   function real_entry(group, name, target, unit, help, greater_than, at_least, below, at_most, attribute, &
                       sweep_list, optional, note, given) result(p)
      character(len=*), intent(in) :: group, name, unit, help
      real(dp), intent(in), target :: target
      real(dp), intent(in), optional :: greater_than, at_least, below, at_most
      character(len=*), intent(in), optional :: attribute, sweep_list, note
      logical, intent(in), optional :: optional
      logical, intent(in), optional, target :: given
      type(parameter_t) :: p
      p = base_entry(group, name, type_real, unit, help, attribute, sweep_list, optional, note)
      call set_bounds(p, greater_than, at_least, below, at_most)
      p%real_value => target
      if (present(given)) p%given => given
   end function real_entry

   !> A list of up to size(target) reals, of which `count` are given.
   function real_list_entry(group, name, target, count, unit, help, greater_than, at_least, below, at_most, &
                            note) result(p)
      character(len=*), intent(in) :: group, name, unit, help
      real(dp), intent(in), target :: target(:)
      integer, intent(in), target :: count
      real(dp), intent(in), optional :: greater_than, at_least, below, at_most
      character(len=*), intent(in), optional :: note
      type(parameter_t) :: p
      p = base_entry(group, name, type_real_list, unit, help, note=note)
      call set_bounds(p, greater_than, at_least, below, at_most)
      p%list_value => target
      p%list_count => count
   end function real_list_entry

   function int_entry(group, name, target, help, at_least, at_most, attribute, sweep_list, note) result(p)
      character(len=*), intent(in) :: group, name, help
      integer, intent(in), target :: target
      integer, intent(in), optional :: at_least, at_most
      character(len=*), intent(in), optional :: attribute, sweep_list, note
      type(parameter_t) :: p
      p = base_entry(group, name, type_int, '', help, attribute, sweep_list, note=note)
      if (present(at_least)) call set_bounds(p, at_least=real(at_least, dp))
      if (present(at_most)) call set_bounds(p, at_most=real(at_most, dp))
      p%int_value => target
   end function int_entry

   !> A text variable: one of `words` (compared in lower case), or any non-empty text that fits.
   function text_entry(group, name, target, help, words, attribute, sweep_list, note) result(p)
      character(len=*), intent(in) :: group, name, help
      character(len=*), intent(in), target :: target
      character(len=*), intent(in), optional :: words, attribute, sweep_list, note
      type(parameter_t) :: p
      p = base_entry(group, name, type_text, '', help, attribute, sweep_list, note=note)
      if (present(words)) p%words = words
      p%text_value => target
   end function text_entry

   function logical_entry(group, name, target, help, attribute) result(p)
      character(len=*), intent(in) :: group, name, help
      logical, intent(in), target :: target
      character(len=*), intent(in), optional :: attribute
      type(parameter_t) :: p
      p = base_entry(group, name, type_logical, '', help, attribute)
      p%logical_value => target
   end function logical_entry

   subroutine set_bounds(p, greater_than, at_least, below, at_most)
      type(parameter_t), intent(inout) :: p
      real(dp), intent(in), optional :: greater_than, at_least, below, at_most
      if (present(greater_than)) then
         p%has_lower = .true.
         p%lower_open = .true.
         p%lower = greater_than
      end if
      if (present(at_least)) then
         p%has_lower = .true.
         p%lower = at_least
      end if
      if (present(below)) then
         p%has_upper = .true.
         p%upper_open = .true.
         p%upper = below
      end if
      if (present(at_most)) then
         p%has_upper = .true.
         p%upper = at_most
      end if
   end subroutine set_bounds

   pure function type_name(type) result(name)
      integer, intent(in) :: type
      character(len=:), allocatable :: name
      select case (type)
      case (type_real)
         name = 'real'
      case (type_int)
         name = 'integer'
      case (type_text)
         name = 'text'
      case (type_logical)
         name = 'logical'
      case default
         name = 'real list'
      end select
   end function type_name

   !> Index of variable `name` of `group` in `table`, 0 if there is none.
   integer function find_parameter(table, group, name)
      type(parameter_t), intent(in) :: table(:)
      character(len=*), intent(in) :: group, name
      integer :: i
      find_parameter = 0
      do i = 1, size(table)
         if (table(i)%group == group .and. table(i)%name == lower(name)) then
            find_parameter = i
            return
         end if
      end do
   end function find_parameter

   !> The names of the variables of `group`, comma separated.
   function entry_names(table, group) result(names)
      type(parameter_t), intent(in) :: table(:)
      character(len=*), intent(in) :: group
      character(len=:), allocatable :: names
      integer :: i
      names = ''
      do i = 1, size(table)
         if (table(i)%group /= group) cycle
         if (len(names) > 0) names = names//', '
         names = names//trim(table(i)%name)
      end do
   end function entry_names

   ! ------------------------------------------------------------------ ranges and checks

   !> A number as short as it reads (ranges and defaults in messages and --help): 0, 10, 0.5, 2e+11.
   function short_number(x) result(text)
      real(dp), intent(in) :: x
      character(len=:), allocatable :: text
      character(len=32) :: buffer
      integer :: e, k
      if (x == aint(x) .and. abs(x) < 1.0e9_dp) then
         write (buffer, '(i0)') int(x, i8)
         text = trim(buffer)
         return
      end if
      if (abs(x) >= 1.0e-3_dp .and. abs(x) < 1.0e9_dp) then
         write (buffer, '(f0.12)') x
         text = trim(buffer)
         do while (text(len(text):len(text)) == '0')
            text = text(1:len(text) - 1)
         end do
         if (text(1:1) == '.') text = '0'//text
         if (len(text) >= 2) then
            if (text(1:2) == '-.') text = '-0'//text(2:)
         end if
         return
      end if
      write (buffer, '(es22.14e3)') x
      buffer = adjustl(buffer)
      e = index(buffer, 'E')
      k = e - 1
      do while (buffer(k:k) == '0')
         k = k - 1
      end do
      if (buffer(k:k) == '.') k = k - 1
      text = buffer(1:k)//'e'//trim(buffer(e + 1:))
      if (text(k + 2:k + 2) == '+') text = text(1:k + 1)//text(k + 3:)
      do while (text(k + 2:k + 2) == '0' .and. len(text) > k + 2)
         text = text(1:k + 1)//text(k + 3:)
      end do
      if (len(text) >= k + 3) then  ! (a one-character exponent has no second character to read)
         if (text(k + 2:k + 3) == '-0') text = text(1:k + 2)//text(k + 4:)
      end if
   end function short_number

   !> A real in full precision without trailing zeros: 12.5, 1.0, 0.10000000000000001; with an exponent,
   !> the fewest digits that read back as `x` (1e-310, -1.7976931348623157e308), as a user types it.
   function plain(x) result(text)
      real(dp), intent(in) :: x
      character(len=:), allocatable :: text
      integer :: dot, e, digits, stat
      character(len=40) :: buffer, form
      real(dp) :: back
      text = str(x)
      dot = index(text, '.')
      e = scan(text, 'eE')
      if (e > 0 .and. ieee_is_finite(x)) then
         do digits = 0, 17
            write (form, '(a,i0,a)') '(es40.', digits, 'e3)'
            write (buffer, form) x
            read (buffer, *, iostat=stat) back
            if (stat == 0 .and. back == x) exit
         end do
         buffer = adjustl(buffer)
         e = scan(buffer, 'eE')
         text = buffer(1:e - 1)
         if (text(len(text):len(text)) == '.') text = text(1:len(text) - 1)
         write (form, '(i0)') read_exponent(buffer(e + 1:))
         text = text//'e'//trim(form)
         return
      end if
      if (dot == 0 .or. e > 0) return
      do while (len(text) > dot + 1)
         if (text(len(text):len(text)) /= '0') exit
         text = text(1:len(text) - 1)
      end do
   end function plain

   integer function read_exponent(text)
      character(len=*), intent(in) :: text
      integer :: stat
      read (text, *, iostat=stat) read_exponent
      if (stat /= 0) read_exponent = 0
   end function read_exponent

   !> What the variable accepts, in words: "finite real > 0 (m)", "integer >= 1", "'usf', 'usl'".
   function allowed_text(p) result(text)
      type(parameter_t), intent(in) :: p
      character(len=:), allocatable :: text
      character(len=:), allocatable :: kind
      integer :: i, start
      select case (p%type)
      case (type_real, type_real_list, type_int)
         kind = merge('finite real', 'integer    ', p%type /= type_int)
         kind = trim(kind)
         if (p%has_lower .and. p%has_upper) then
            text = kind//' with '//bound(p%lower)//' '//trim(merge('< ', '<=', p%lower_open))//' '// &
                   trim(p%name)//' '//trim(merge('< ', '<=', p%upper_open))//' '//bound(p%upper)
         else if (p%has_lower) then
            text = kind//' '//trim(merge('> ', '>=', p%lower_open))//' '//bound(p%lower)
         else if (p%has_upper) then
            text = kind//' '//trim(merge('< ', '<=', p%upper_open))//' '//bound(p%upper)
         else
            text = 'any '//kind
         end if
         if (p%type == type_real_list) text = 'up to '//str(size(p%list_value))//' values, each '//text
      case (type_text)
         if (len_trim(p%words) == 0) then
            text = 'quoted text of 1 to '//str(len(p%text_value))//' characters'
         else
            text = ''
            start = 1
            do i = 1, len_trim(p%words) + 1
               if (i <= len_trim(p%words)) then
                  if (p%words(i:i) /= ',') cycle
               end if
               if (len(text) > 0) text = text//', '
               text = text//"'"//trim(adjustl(p%words(start:i - 1)))//"'"
               start = i + 1
            end do
         end if
      case default
         text = '.true. or .false.'
      end select
      if (len_trim(p%unit) > 0) text = text//' ('//trim(p%unit)//')'
      if (len_trim(p%note) > 0) text = text//'; '//trim(p%note)
   contains
      !> A bound as the user would type it: integers in full, reals short.
      function bound(x) result(b)
         real(dp), intent(in) :: x
         character(len=:), allocatable :: b
         if (p%type == type_int) then
            b = str(nint(x, i8))
         else
            b = short_number(x)
         end if
      end function bound
   end function allowed_text

   !> Is `x` within the range of `p`?
   logical function real_in_range(p, x)
      type(parameter_t), intent(in) :: p
      real(dp), intent(in) :: x
      real_in_range = ieee_is_finite(x)
      if (.not. real_in_range) return
      ! a subnormal number (0 < |x| < 2.2e-308) has lost precision already: not a value to compute with
      real_in_range = x == 0.0_dp .or. abs(x) >= tiny(x)
      if (.not. real_in_range) return
      if (p%has_lower) then
         if (x < p%lower .or. (p%lower_open .and. x == p%lower)) real_in_range = .false.
      end if
      if (p%has_upper) then
         if (x > p%upper .or. (p%upper_open .and. x == p%upper)) real_in_range = .false.
      end if
   end function real_in_range

   !> Is `word` allowed for text variable `p`?
   logical function word_allowed(p, word)
      type(parameter_t), intent(in) :: p
      character(len=*), intent(in) :: word
      if (len_trim(p%words) == 0) then
         word_allowed = len_trim(word) > 0
      else
         word_allowed = index(','//remove_blanks(p%words)//',', ','//trim(word)//',') > 0 .and. &
                        len_trim(word) > 0 .and. index(trim(word), ',') == 0
      end if
   end function word_allowed

   pure function remove_blanks(text) result(compact)
      character(len=*), intent(in) :: text
      character(len=:), allocatable :: compact
      integer :: i
      compact = ''
      do i = 1, len_trim(text)
         if (text(i:i) /= ' ') compact = compact//text(i:i)
      end do
   end function remove_blanks

   !> Check the bound value of `p` against its range; `where` prefixes the message (e.g. "file:3: ").
   subroutine check_parameter(p, error, where)
      type(parameter_t), intent(in) :: p
      type(error_t), allocatable, intent(inout) :: error
      character(len=*), intent(in), optional :: where
      character(len=:), allocatable :: prefix
      integer :: k
      prefix = ''
      if (present(where)) prefix = where
      select case (p%type)
      case (type_real)
         if (.not. has_value(p)) return ! an optional variable not given
         if (.not. real_in_range(p, p%real_value)) call out_of_range(plain(p%real_value), trim(p%name), p%real_value)
      case (type_int)
         if (.not. real_in_range(p, real(p%int_value, dp))) call out_of_range(str(p%int_value), trim(p%name), 1.0_dp)
      case (type_text)
         if (.not. word_allowed(p, p%text_value)) then
            if (len_trim(p%words) > 0) then
               call append_error(error, prefix//trim(p%group)//": "//trim(p%name)//" = "//quoted(trim(p%text_value))// &
                                 " is unknown; allowed: "//allowed_text(p))
            else
               call append_error(error, prefix//trim(p%group)//": "//trim(p%name)//" is empty; allowed: "// &
                                 allowed_text(p))
            end if
         end if
      case (type_real_list)
         do k = 1, p%list_count
            if (.not. real_in_range(p, p%list_value(k))) &
               call out_of_range(plain(p%list_value(k)), trim(p%name)//'('//str(k)//')', p%list_value(k))
         end do
      end select
   contains
      subroutine out_of_range(value, label, x)
         character(len=*), intent(in) :: value, label
         real(dp), intent(in) :: x
         character(len=:), allocatable :: why
         why = ''
         if (x /= 0.0_dp .and. abs(x) < tiny(x)) why = ' (a subnormal number: below 2.2e-308, the smallest '// &
                                                       'normal double, numbers lose precision)'
         call append_error(error, prefix//trim(p%group)//": "//label//" = "//value//" is out of range"//why// &
                           "; allowed: "//allowed_text(p))
      end subroutine out_of_range
   end subroutine check_parameter

   ! ------------------------------------------------------------------ values from text

   !> Convert `values` for `p` and store them through its pointer; on a problem append a message
   !> naming `where` (file and line), the group, the variable and what it accepts.
   subroutine set_parameter(p, values, where, error)
      type(parameter_t), intent(inout) :: p
      type(nml_value_t), intent(in) :: values(:)
      character(len=*), intent(in) :: where
      type(error_t), allocatable, intent(inout) :: error
      character(len=:), allocatable :: problem
      integer :: given, k

      given = count(.not. values%null)
      if (given == 0) then
         call append_error(error, where//trim(p%group)//": '"//trim(p%name)//"' has no value; allowed: "// &
                           allowed_text(p))
         return
      end if
      if (p%type /= type_real_list) then
         if (size(values) > 1) then
            call append_error(error, where//trim(p%group)//": '"//trim(p%name)//"' takes one value, "// &
                              str(size(values))//" given; allowed: "//allowed_text(p))
            return
         end if
      else
         if (any(values(given + 1:)%null) .or. any(values(1:given)%null)) then
            call append_error(error, where//trim(p%group)//": '"//trim(p%name)//"' has a gap (an empty value); "// &
                              "give values contiguously")
            return
         end if
         if (given > size(p%list_value)) then
            call append_error(error, where//trim(p%group)//": '"//trim(p%name)//"' has "//str(given)// &
                              " values; allowed: "//allowed_text(p))
            return
         end if
      end if
      do k = 1, size(values)
         problem = value_problem(p, values(k))
         if (len(problem) > 0) then
            call append_error(error, where//trim(p%group)//": bad value for '"//trim(p%name)//"': "//problem// &
                              "; allowed: "//allowed_text(p))
            return
         end if
      end do
      if (associated(p%given)) p%given = .true.
      select case (p%type)
      case (type_real)
         p%real_value = real_value(values(1))
      case (type_int)
         p%int_value = int_value(values(1))
      case (type_logical)
         p%logical_value = logical_value(values(1))
      case (type_text)
         p%text_value = text_value(p, values(1))
      case (type_real_list)
         p%list_count = given
         p%list_value = 0.0_dp
         do k = 1, given
            p%list_value(k) = real_value(values(k))
         end do
      end select
   end subroutine set_parameter

   !> What is wrong with `value` as a value of `p` ('' if it converts).
   function value_problem(p, value) result(problem)
      type(parameter_t), intent(in) :: p
      type(nml_value_t), intent(in) :: value
      character(len=:), allocatable :: problem
      character(len=:), allocatable :: word
      integer(i8) :: big
      integer :: stat
      problem = ''
      if (p%type == type_text) then
         if (.not. value%quoted) then
            problem = value%text//' is not quoted text'
         else if (len(value%text) > len(p%text_value)) then
            problem = quoted(value%text)//' is longer than '//str(len(p%text_value))//' characters'
         end if
         return
      end if
      if (value%quoted) then
         problem = quoted(value%text)//' is text, not '//article(type_name(p%type))
         return
      end if
      word = lower(value%text)
      select case (p%type)
      case (type_logical)
         select case (word)
         case ('t', 'f', '.t.', '.f.', '.true.', '.false.', 'true', 'false', '.t', '.f')
         case default
            problem = value%text//' is not a logical'
         end select
      case (type_int)
         if (verify(word(1:1), '+-0123456789') /= 0 .or. verify(word(2:), '0123456789') /= 0 .or. &
             verify(word, '+-') == 0) then
            problem = value%text//' is not a whole number'
         else
            read (word, *, iostat=stat) big
            if (stat /= 0 .or. len(word) > 19 .or. abs(big) > huge(1)) &
               problem = value%text//' is beyond the integers of this program (at most '//str(huge(1))//')'
         end if
      case default ! real
         select case (word)
         case ('nan', 'inf', '+inf', '-inf', 'infinity', '+infinity', '-infinity')
         case default
            if (verify(word, '+-0123456789.ed') /= 0 .or. scan(word, '0123456789') == 0) then
               problem = value%text//' is not a real number'
            else
               block
                  real(dp) :: x
                  read (word, *, iostat=stat) x
               end block
               if (stat /= 0) problem = value%text//' is not a real number'
            end if
         end select
      end select
   end function value_problem

   pure function article(word) result(text)
      character(len=*), intent(in) :: word
      character(len=:), allocatable :: text
      if (scan(word(1:1), 'aeiou') > 0) then
         text = 'an '//word
      else
         text = 'a '//word
      end if
   end function article

   real(dp) function real_value(value)
      type(nml_value_t), intent(in) :: value
      integer :: stat
      read (value%text, *, iostat=stat) real_value
      if (stat /= 0) real_value = 0.0_dp
   end function real_value

   integer function int_value(value)
      type(nml_value_t), intent(in) :: value
      integer :: stat
      read (value%text, *, iostat=stat) int_value
      if (stat /= 0) int_value = 0
   end function int_value

   logical function logical_value(value)
      type(nml_value_t), intent(in) :: value
      character(len=:), allocatable :: word
      word = lower(value%text)
      if (word(1:1) == '.') word = word(2:)
      logical_value = word(1:1) == 't'
   end function logical_value

   !> Text of a text variable: lower case when the variable takes keywords.
   function text_value(p, value) result(text)
      type(parameter_t), intent(in) :: p
      type(nml_value_t), intent(in) :: value
      character(len=:), allocatable :: text
      if (len_trim(p%words) > 0) then
         text = lower(value%text)
      else
         text = value%text
      end if
   end function text_value

   ! ------------------------------------------------------------------ lists of values (&sweep)

   !> Read `values` as a list of values of variable `p` (each converted and range-checked as `p`
   !> itself would be); messages name the list `name` and the element: "sweep: elements(2) = 0 ...".
   subroutine read_value_list(p, name, values, where, list, error)
      type(parameter_t), intent(in) :: p
      character(len=*), intent(in) :: name, where
      type(nml_value_t), intent(in) :: values(:)
      type(value_list_t), intent(out) :: list
      type(error_t), allocatable, intent(inout) :: error
      type(parameter_t) :: one
      real(dp), target :: r
      integer, target :: i
      character(len=:), allocatable, target :: t
      integer :: k, given
      r = 0.0_dp
      i = 0
      call describe_list(list, p, name)
      given = count(.not. values%null)
      if (given == 0) then
         call append_error(error, where//"sweep: "//trim(name)//" is an empty list; allowed: one or more values")
         return
      end if
      if (any(values(1:given)%null)) then
         call append_error(error, where//"sweep: "//trim(name)//" has a gap (an empty value); give values "// &
                           "contiguously")
         return
      end if
      allocate (list%reals(given), list%ints(given), list%texts(given))
      list%reals = 0.0_dp
      list%ints = 0
      list%texts = ''
      do k = 1, given
         one = p
         one%group = 'sweep'
         one%name = trim(name)//'('//str(k)//')'
         one%optional = .false.
         nullify (one%given)
         select case (p%type)
         case (type_real)
            one%real_value => r
         case (type_int)
            one%int_value => i
         case (type_text)
            allocate (character(len=len(p%text_value)) :: t)
            one%text_value => t
         end select
         given = 0
         if (allocated(error)) given = len(error%message)
         call set_parameter(one, values(k:k), where, error)
         if (.not. allocated(error)) then
            call check_parameter(one, error, where)
         else if (len(error%message) == given) then
            call check_parameter(one, error, where)
         end if
         select case (p%type)
         case (type_real)
            list%reals(k) = r
         case (type_int)
            list%ints(k) = i
         case (type_text)
            list%texts(k) = t
            deallocate (t)
         end select
      end do
   end subroutine read_value_list

   !> A list holding just the current value of `p` (a list left out sweeps over the base value).
   function single_value_list(p, name) result(list)
      type(parameter_t), intent(in) :: p
      character(len=*), intent(in) :: name
      type(value_list_t) :: list
      call describe_list(list, p, name)
      allocate (list%reals(1), list%ints(1), list%texts(1))
      list%reals = 0.0_dp
      list%ints = 0
      list%texts = ''
      select case (p%type)
      case (type_real)
         list%reals = p%real_value
      case (type_int)
         list%ints = p%int_value
      case (type_text)
         list%texts = p%text_value
      end select
   end function single_value_list

   subroutine describe_list(list, p, name)
      type(value_list_t), intent(inout) :: list
      type(parameter_t), intent(in) :: p
      character(len=*), intent(in) :: name
      list%name = name
      list%alias = p%sweep_alias
      list%type = p%type
      list%column = p%attribute
      if (p%type == type_text) list%width = len(p%text_value)
   end subroutine describe_list

   !> Number of values of a list.
   pure integer function list_size(list)
      class(value_list_t), intent(in) :: list
      list_size = 0
      if (allocated(list%reals)) list_size = size(list%reals)
   end function list_size

   !> Set `p` to value `k` of `list`.
   subroutine set_from_list(p, list, k)
      type(parameter_t), intent(inout) :: p
      type(value_list_t), intent(in) :: list
      integer, intent(in) :: k
      select case (p%type)
      case (type_real)
         p%real_value = list%reals(k)
      case (type_int)
         p%int_value = list%ints(k)
      case (type_text)
         p%text_value = list%texts(k)
      end select
   end subroutine set_from_list

   !> The values of a list as namelist text, full precision: "1, 3, 7" or "'usf', 'usl'".
   function list_text(list) result(text)
      type(value_list_t), intent(in) :: list
      character(len=:), allocatable :: text
      integer :: k
      text = ''
      do k = 1, list%size()
         select case (list%type)
         case (type_real)
            text = text//str(list%reals(k))
         case (type_int)
            text = text//str(list%ints(k))
         case default
            text = text//quoted(trim(list%texts(k)))
         end select
         if (k < list%size()) text = text//', '
      end do
   end function list_text

   ! ------------------------------------------------------------------ the namelist reader

   !> Read every group of `path` into assignments. Refused: text outside a group, a group without
   !> its closing '/', a value without a name. `groups` receives the group names in file order.
   subroutine read_namelist(path, items, groups, group_lines, error)
      character(len=*), intent(in) :: path
      type(nml_item_t), allocatable, intent(out) :: items(:)
      character(len=32), allocatable, intent(out) :: groups(:)
      integer, allocatable, intent(out) :: group_lines(:)
      type(error_t), allocatable, intent(out) :: error
      character(len=:), allocatable :: text

      allocate (items(0), groups(0), group_lines(0))
      call read_input_text(path, text, error)
      if (allocated(error)) return
      call parse_namelist(text, path, items, groups, group_lines, error)
   end subroutine read_namelist

   !> The whole text of input file `path`, read once ('-': standard input, to its end). A FIFO or other
   !> stream (`mpm1d <(...)`) is read once to its end as standard input is: it cannot be read twice.
   subroutine read_input_text(path, text, error)
      use, intrinsic :: iso_fortran_env, only: input_unit
      use mpm_files, only: path_kind, path_other
      character(len=*), intent(in) :: path
      character(len=:), allocatable, intent(out) :: text
      type(error_t), allocatable, intent(out) :: error
      integer :: n, unit, stat
      logical :: is_folder, stream
      character(len=512) :: msg

      text = ''
      if (path == '-') then
         call read_stream(input_unit, 'standard input')
         return
      end if
      inquire (file=trim(path)//'/.', exist=is_folder)
      if (is_folder) then
         call set_error(error, "input file '"//trim(path)//"' is a folder; allowed: a namelist file")
         return
      end if
      stream = path_kind(path) == path_other
      if (stream) then
         open (newunit=unit, file=path, status='old', action='read', form='formatted', access='sequential', &
               iostat=stat, iomsg=msg)
      else
         open (newunit=unit, file=path, status='old', action='read', access='stream', form='unformatted', &
               iostat=stat, iomsg=msg)
      end if
      if (stat /= 0) then
         call set_error(error, "cannot open input file '"//trim(path)//"': "//trim(msg))
         return
      end if
      if (stream) then
         call read_stream(unit, "input file '"//trim(path)//"'")
         close (unit)
         return
      end if
      inquire (unit=unit, size=n)
      deallocate (text)
      allocate (character(len=max(n, 0)) :: text)
      stat = 0
      if (n > 0) read (unit, iostat=stat, iomsg=msg) text
      close (unit)
      if (stat /= 0) then
         call set_error(error, "cannot read input file '"//trim(path)//"': "//trim(msg))
         return
      end if
   contains
      !> Read `unit` line by line to its end (each line ends in a newline in `text`).
      subroutine read_stream(unit, name)
         integer, intent(in) :: unit
         character(len=*), intent(in) :: name
         character(len=4096) :: chunk
         integer :: got
         do
            read (unit, '(a)', advance='no', iostat=stat, size=got) chunk
            if (is_iostat_end(stat)) exit
            if (stat /= 0 .and. .not. is_iostat_eor(stat)) then
               call set_error(error, 'cannot read the namelist from '//name)
               return
            end if
            text = text//chunk(1:got)
            if (is_iostat_eor(stat)) text = text//new_line('a')
         end do
      end subroutine read_stream
   end subroutine read_input_text

   !> Command-line overrides `group.name=value[, value ...]`: each is read by the namelist reader as
   !> "&group name=value /" and replaces the input's assignment of that variable (or adds one); a later
   !> override of the same variable replaces an earlier one. Messages name the override as typed.
   !> `known_groups`: the groups an override may name.
   subroutine add_overrides(items, overrides, known_groups, error)
      type(nml_item_t), allocatable, intent(inout) :: items(:)
      character(len=*), intent(in) :: overrides(:), known_groups(:)
      type(error_t), allocatable, intent(inout) :: error
      type(nml_item_t), allocatable :: parsed(:), kept(:)
      character(len=32), allocatable :: groups(:)
      integer, allocatable :: lines(:)
      type(error_t), allocatable :: problem
      character(len=:), allocatable :: text, origin, group, name, known
      integer :: i, j, n, dot, eq

      known = ''
      do i = 1, size(known_groups)
         if (i > 1) known = known//', '
         known = known//trim(known_groups(i))
      end do
      do i = 1, size(overrides)
         text = trim(overrides(i))
         origin = "command line '"//text//"'"
         eq = index(text, '=')
         dot = 0
         if (eq > 1) dot = index(text(1:eq - 1), '.')
         if (dot < 2 .or. dot >= eq - 1) then
            call append_error(error, origin//": not an override; allowed: group.name=value, "// &
                              "e.g. discretisation.elements=40")
            cycle
         end if
         group = lower(text(1:dot - 1))
         name = lower(trim(text(dot + 1:eq - 1)))
         if (.not. any(known_groups == group)) then
            call append_error(error, origin//": unknown namelist group '"//group//"' (known groups: "//known//")")
            cycle
         end if
         call parse_namelist('&'//group//' '//name//' = '//bare_words_quoted(text(eq + 1:))//' /', origin, parsed, &
                             groups, lines, problem)
         if (allocated(problem)) then
            call append_error(error, replace_all(problem%message, origin//':1: ', origin//': '))
            deallocate (problem)
            cycle
         end if
         if (size(parsed) /= 1) then
            call append_error(error, origin//": not one assignment; allowed: group.name=value")
            cycle
         end if
         parsed(1)%origin = origin//': '
         allocate (kept(0))
         n = 0
         do j = 1, size(items)
            if (items(j)%group == parsed(1)%group .and. items(j)%name == parsed(1)%name) cycle
            kept = [kept, items(j)]
         end do
         items = [kept, parsed(1)]
         deallocate (kept)
      end do
   end subroutine add_overrides

   !> An override's value as the shell leaves it: without any quote, each comma-separated word that is
   !> neither a number nor a logical is text and gets quotes (discretisation.scheme=musl is 'musl').
   function bare_words_quoted(value) result(text)
      character(len=*), intent(in) :: value
      character(len=:), allocatable :: text, word
      integer :: start, comma, stat
      real(dp) :: x
      if (scan(value, '"'//"'") > 0) then
         text = value
         return
      end if
      text = ''
      start = 1
      do
         comma = index(value(start:), ',')
         if (comma == 0) then
            word = trim(adjustl(value(start:)))
         else
            word = trim(adjustl(value(start:start + comma - 2)))
         end if
         ! a number: digits, sign, point and exponent only (list-directed reading alone would take
         ! '/tmp/a.h5' as an empty value), or NaN and Infinity, which the checks then refuse by name
         stat = 1
         if (verify(word, '0123456789+-.eEdD') == 0) read (word, *, iostat=stat) x
         if (len(word) > 0 .and. stat /= 0 .and. .not. any(lower(word) == [character(len=9) :: 't', 'f', &
             '.true.', '.false.', '.t.', '.f.', 'nan', 'inf', 'infinity', '+inf', '-inf', '+infinity', '-infinity'])) &
            word = "'"//word//"'"
         text = text//word
         if (comma == 0) exit
         text = text//', '
         start = start + comma
      end do
   end function bare_words_quoted

   !> How messages name where `item` was given: "path:line: " or its override's origin.
   function item_place(item, path) result(place)
      type(nml_item_t), intent(in) :: item
      character(len=*), intent(in) :: path
      character(len=:), allocatable :: place
      if (allocated(item%origin)) then
         place = item%origin
      else
         place = trim(path)//":"//str(item%line)//": "
      end if
   end function item_place

   pure function replace_all(text, old, new) result(out)
      character(len=*), intent(in) :: text, old, new
      character(len=:), allocatable :: out
      integer :: k, start
      out = ''
      start = 1
      do
         k = index(text(start:), old)
         if (k == 0) exit
         out = out//text(start:start + k - 2)//new
         start = start + k - 1 + len(old)
      end do
      out = out//text(start:)
   end function replace_all

   !> Parse namelist `text` (from `source`, named in messages as "source:line: ") into assignments.
   !> Also the way for other text to reach the registry, e.g. a command-line override
   !> `group.name=value` given as "&group name=value /".
   subroutine parse_namelist(text, source, items, groups, group_lines, error)
      character(len=*), intent(in) :: text, source
      type(nml_item_t), allocatable, intent(out) :: items(:)
      character(len=32), allocatable, intent(out) :: groups(:)
      integer, allocatable, intent(out) :: group_lines(:)
      type(error_t), allocatable, intent(out) :: error
      character(len=:), allocatable :: group, path
      integer, allocatable :: line_of(:)
      integer :: pos, group_line, nvalues, nitems
      type(nml_item_t) :: item

      path = source
      nvalues = 0
      nitems = 0
      allocate (items(0), groups(0), group_lines(0))
      allocate (line_of(len(text) + 1))
      line_of(1) = 1
      do pos = 2, len(text) + 1
         line_of(pos) = line_of(pos - 1)
         if (text(pos - 1:pos - 1) == new_line('a')) line_of(pos) = line_of(pos) + 1
      end do

      pos = 1
      do
         call skip_blanks_and_comments()
         if (pos > len(text) .or. too_many()) exit
         if (text(pos:pos) /= '&') then
            call append_error(error, where(pos)//"text outside a namelist group: '"//line_text(pos)// &
                              "'; allowed: &group name=value, ... / and comments after '!'")
            call skip_line()
            cycle
         end if
         group_line = line_of(pos)
         pos = pos + 1
         group = lower(identifier())
         if (len(group) == 0) then
            call append_error(error, where(pos)//"'&' without a group name")
            call skip_line()
            cycle
         end if
         if (any(groups == group)) call append_error(error, trim(path)//":"//str(group_line)//": group &"// &
                                                       group//" is given twice")
         groups = [character(len=32) :: groups, group]
         group_lines = [group_lines, group_line]
         call read_group()
      end do
      items = items(1:nitems)
   contains
      !> Past the problems an error lists, reading stops (the rest of a binary or garbage file adds nothing).
      logical function too_many()
         too_many = .false.
         if (allocated(error)) too_many = error%problems > 100
      end function too_many

      function where(at) result(prefix)
         integer, intent(in) :: at
         character(len=:), allocatable :: prefix
         prefix = trim(path)//":"//str(line_of(min(at, size(line_of))))//": "
      end function where

      function line_text(at) result(line)
         integer, intent(in) :: at
         character(len=:), allocatable :: line
         integer :: last
         last = index(text(at:), new_line('a'))
         if (last == 0) then
            line = trim(text(at:min(len(text), at + 60)))
         else
            line = trim(text(at:min(at + last - 2, at + 60)))
         end if
      end function line_text

      subroutine skip_line()
         do while (pos <= len(text))
            if (text(pos:pos) == new_line('a')) exit
            pos = pos + 1
         end do
      end subroutine skip_line

      logical function blank(c)
         character(len=1), intent(in) :: c
         blank = c == ' ' .or. c == achar(9) .or. c == new_line('a') .or. c == achar(13)
      end function blank

      subroutine skip_blanks_and_comments()
         do while (pos <= len(text))
            if (text(pos:pos) == '!') then
               call skip_line()
            else if (blank(text(pos:pos))) then
               pos = pos + 1
            else
               exit
            end if
         end do
      end subroutine skip_blanks_and_comments

      function identifier() result(name)
         character(len=:), allocatable :: name
         integer :: start
         start = pos
         do while (pos <= len(text))
            if (index(identifier_characters, text(pos:pos)) == 0) exit
            pos = pos + 1
         end do
         name = text(start:pos - 1)
      end function identifier

      !> Is an identifier followed by '=' at `pos`? (the start of the next assignment)
      logical function assignment_ahead()
         integer :: k
         assignment_ahead = .false.
         k = pos
         if (index('abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ', text(k:k)) == 0) return
         do while (k <= len(text))
            if (index(identifier_characters, text(k:k)) == 0) exit
            k = k + 1
         end do
         do while (k <= len(text))
            if (.not. blank(text(k:k))) exit
            k = k + 1
         end do
         if (k > len(text)) return
         assignment_ahead = text(k:k) == '=' .or. text(k:k) == '('
      end function assignment_ahead

      subroutine read_group()
         logical :: have_item, after_value
         type(nml_value_t) :: value
         integer :: repeat, stat, star
         have_item = .false.
         after_value = .false.
         do
            call skip_blanks_and_comments()
            if (too_many()) return
            if (pos > len(text)) then
               call append_error(error, trim(path)//":"//str(group_line)//": group &"//group// &
                                 ": not terminated by '/' (end of file reached)")
               call finish_item()
               return
            end if
            if (text(pos:pos) == '/') then
               pos = pos + 1
               call finish_item()
               return
            end if
            if (end_marker()) then ! the older terminator '&end'
               pos = pos + 4
               call finish_item()
               return
            end if
            if (text(pos:pos) == '&') then
               call append_error(error, where(pos)//"group &"//group//": not terminated by '/' before the next group")
               call finish_item()
               return
            end if
            if (text(pos:pos) == ',') then
               if (.not. after_value .and. have_item) call add_value(nml_value_t(text='', null=.true.))
               after_value = .false.
               pos = pos + 1
               cycle
            end if
            if (assignment_ahead()) then
               call finish_item()
               item%group = group
               item%line = line_of(pos)
               item%name = lower(identifier())
               allocate (item%values(0))
               nvalues = 0
               call skip_blanks_and_comments()
               if (text(pos:pos) == '(') then
                  call append_error(error, where(pos)//"group &"//group//": '"//item%name//"(...)': indexed "// &
                                    "assignment is not supported; give the whole list")
                  do while (pos <= len(text))
                     if (text(pos:pos) == '=') exit
                     pos = pos + 1
                  end do
               end if
               pos = pos + 1 ! the '='
               have_item = .true.
               after_value = .false.
               cycle
            end if
            if (.not. have_item) then
               call append_error(error, where(pos)//"group &"//group//": value '"//token_text()// &
                                 "' without a name; allowed: name = value")
               call skip_token()
               cycle
            end if
            ! a value, maybe with a repeat count r*
            repeat = 1
            star = 0
            if (.not. quote_at(pos)) star = repeat_star()
            if (star > 0) then
               read (text(pos:star - 1), *, iostat=stat) repeat
               if (stat /= 0 .or. repeat < 1 .or. repeat > 100000) then
                  call append_error(error, where(pos)//"group &"//group//": bad repeat count '"// &
                                    text(pos:star - 1)//"' for '"//item%name//"'")
                  repeat = 1
               end if
               pos = star + 1
               if (pos > len(text)) then
                  value = nml_value_t(text='', null=.true.)
               else if (blank(text(pos:pos)) .or. text(pos:pos) == ',' .or. text(pos:pos) == '/') then
                  value = nml_value_t(text='', null=.true.)
               else
                  value = next_value()
               end if
            else
               value = next_value()
            end if
            do stat = 1, repeat
               call add_value(value)
            end do
            after_value = .true.
         end do
      end subroutine read_group

      !> Is '&end' (not followed by a name character) at pos?
      logical function end_marker()
         end_marker = .false.
         if (pos + 3 > len(text)) return
         if (lower(text(pos:pos + 3)) /= '&end') return
         end_marker = .true.
         if (pos + 4 <= len(text)) end_marker = index(identifier_characters, text(pos + 4:pos + 4)) == 0
      end function end_marker

      logical function quote_at(k)
         integer, intent(in) :: k
         quote_at = text(k:k) == "'" .or. text(k:k) == '"'
      end function quote_at

      !> Position of the '*' of a repeat count `digits*` at pos, 0 if none.
      integer function repeat_star()
         integer :: k
         repeat_star = 0
         k = pos
         do while (k <= len(text))
            if (index('0123456789', text(k:k)) == 0) exit
            k = k + 1
         end do
         if (k > pos .and. k <= len(text)) then
            if (text(k:k) == '*') repeat_star = k
         end if
      end function repeat_star

      function next_value() result(value)
         type(nml_value_t) :: value
         character(len=1) :: quote
         if (quote_at(pos)) then
            quote = text(pos:pos)
            value%quoted = .true.
            value%text = ''
            pos = pos + 1
            do
               if (pos > len(text)) then
                  call append_error(error, where(pos)//"group &"//group//": text for '"//item%name// &
                                    "' has no closing quote")
                  return
               end if
               if (text(pos:pos) == new_line('a')) then ! no text value spans lines: a quote is missing
                  call append_error(error, where(pos)//"group &"//group//": text for '"//item%name// &
                                    "' runs past the end of its line (a closing quote missing, or a line break "// &
                                    "in the text); allowed: quoted text on one line")
                  return
               end if
               if (text(pos:pos) == quote) then
                  if (pos < len(text)) then
                     if (text(pos + 1:pos + 1) == quote) then
                        value%text = value%text//quote
                        pos = pos + 2
                        cycle
                     end if
                  end if
                  pos = pos + 1
                  exit
               end if
               value%text = value%text//text(pos:pos)
               pos = pos + 1
            end do
         else
            value%text = token_text()
            call skip_token()
         end if
      end function next_value

      function token_text() result(token)
         character(len=:), allocatable :: token
         integer :: k
         k = pos
         do while (k <= len(text))
            if (blank(text(k:k)) .or. index(',/!&', text(k:k)) > 0) exit
            k = k + 1
         end do
         token = text(pos:k - 1)
      end function token_text

      subroutine skip_token()
         pos = pos + max(len(token_text()), 1)
      end subroutine skip_token

      !> Append `value` to the item's values (storage doubled when full: a list of 100,000 values, or a
      !> repeat count, is read in linear time; finish_item trims it to `nvalues`).
      subroutine add_value(value)
         type(nml_value_t), intent(in) :: value
         type(nml_value_t), allocatable :: grown(:)
         if (nvalues == size(item%values)) then
            allocate (grown(max(8, 2*nvalues)))
            grown(1:nvalues) = item%values(1:nvalues)
            call move_alloc(grown, item%values)
         end if
         nvalues = nvalues + 1
         item%values(nvalues) = value
      end subroutine add_value

      subroutine finish_item()
         type(nml_item_t), allocatable :: grown(:)
         if (allocated(item%values)) then
            item%values = item%values(1:nvalues)
            if (nitems == size(items)) then ! doubled when full, trimmed at the end
               allocate (grown(max(8, 2*nitems)))
               grown(1:nitems) = items(1:nitems)
               call move_alloc(grown, items)
            end if
            nitems = nitems + 1
            items(nitems) = item
            deallocate (item%values)
         end if
         nvalues = 0
      end subroutine finish_item
   end subroutine parse_namelist

   !> Apply the assignments of `group` to `table`: unknown and repeated names and values that do
   !> not convert are reported, with file and line.
   subroutine apply_items(table, items, group, path, error)
      type(parameter_t), intent(inout) :: table(:)
      type(nml_item_t), intent(in) :: items(:)
      character(len=*), intent(in) :: group, path
      type(error_t), allocatable, intent(inout) :: error
      integer :: i, k
      character(len=:), allocatable :: where
      do i = 1, size(items)
         if (items(i)%group /= group) cycle
         where = item_place(items(i), path)
         k = find_parameter(table, group, items(i)%name)
         if (k == 0) then
            call append_error(error, where//"group &"//group//": unknown variable '"//items(i)%name// &
                              "'; allowed names: "//entry_names(table, group))
            cycle
         end if
         if (table(k)%line > 0) then
            call append_error(error, where//group//": '"//trim(table(k)%name)//"' is given twice (also line "// &
                              str(table(k)%line)//")")
            cycle
         end if
         table(k)%line = items(i)%line
         table(k)%origin = where
         call set_parameter(table(k), items(i)%values, where, error)
      end do
   end subroutine apply_items

   ! ------------------------------------------------------------------ text made from the table

   !> Text in quotes, a quote inside doubled.
   function quoted(text) result(q)
      character(len=*), intent(in) :: text
      character(len=:), allocatable :: q
      integer :: i
      q = "'"
      do i = 1, len(text)
         q = q//text(i:i)
         if (text(i:i) == "'") q = q//"'"
      end do
      q = q//"'"
   end function quoted

   !> The value of `p` as namelist text, full precision ('' for an unset optional or empty list).
   function format_value(p) result(text)
      type(parameter_t), intent(in) :: p
      character(len=:), allocatable :: text
      integer :: k
      select case (p%type)
      case (type_real)
         text = str(p%real_value)
         if (.not. has_value(p)) text = ''
      case (type_int)
         text = str(p%int_value)
      case (type_logical)
         text = merge('T', 'F', p%logical_value)
      case (type_text)
         text = quoted(trim(p%text_value))
      case default
         text = ''
         do k = 1, p%list_count
            text = text//str(p%list_value(k))
            if (k < p%list_count) text = text//', '
         end do
      end select
   end function format_value

   !> Does `p` have a value? False only for an optional variable whose "given" flag is unset.
   pure logical function has_value(p)
      type(parameter_t), intent(in) :: p
      has_value = .true.
      if (p%optional .and. associated(p%given)) has_value = p%given
   end function has_value

   !> Whether scene kind `kind` uses the variable `p` (its `kinds` list is empty or names `kind`).
   pure logical function used_by(p, kind)
      type(parameter_t), intent(in) :: p
      character(len=*), intent(in) :: kind
      used_by = len_trim(p%kinds) == 0 .or. index(','//remove_blanks(p%kinds)//',', ','//trim(kind)//',') > 0
   end function used_by

   !> `p` restricted to the scene kinds `kinds` (comma separated), for the table's constructors.
   function for_kinds(p, kinds) result(q)
      type(parameter_t), intent(in) :: p
      character(len=*), intent(in) :: kinds
      type(parameter_t) :: q
      q = p
      q%kinds = kinds
   end function for_kinds

   !> `&group name=value, ... /` for every variable of `group` that has a value (and, when `kind` is
   !> given, that scene kind uses).
   function group_namelist(table, group, kind) result(text)
      type(parameter_t), intent(in) :: table(:)
      character(len=*), intent(in) :: group
      character(len=*), intent(in), optional :: kind
      character(len=:), allocatable :: text, value
      integer :: i
      text = '&'//group
      do i = 1, size(table)
         if (table(i)%group /= group) cycle
         if (present(kind)) then
            if (.not. used_by(table(i), kind)) cycle
         end if
         value = format_value(table(i))
         if (len(value) == 0) cycle
         if (text /= '&'//group) text = text//','
         text = text//' '//trim(table(i)%name)//'='//value
      end do
      text = text//' /'
   end function group_namelist

   !> The table as tab-separated lines with a header: group, name, attribute, type, unit, value,
   !> allowed, sweep list, its former name, help. Read by the Python loader (postprocess/mpm1d_io.py).
   function parameter_listing(table) result(text)
      type(parameter_t), intent(in) :: table(:)
      character(len=:), allocatable :: text
      character(len=*), parameter :: tab = achar(9), nl = new_line('a')
      integer :: i
      text = 'group'//tab//'name'//tab//'attribute'//tab//'type'//tab//'unit'//tab//'value'//tab//'allowed'// &
             tab//'sweep_list'//tab//'sweep_alias'//tab//'help'
      do i = 1, size(table)
         associate (p => table(i))
            text = text//nl//trim(p%group)//tab//trim(p%name)//tab//trim(p%attribute)//tab//type_name(p%type)// &
                   tab//trim(p%unit)//tab//format_value(p)//tab//allowed_text(p)//tab//trim(p%sweep_list)//tab// &
                   trim(p%sweep_alias)//tab//trim(p%help)
         end associate
      end do
   end function parameter_listing

   !> --help lines for the variables of `group` (defaults from the table's values).
   function parameter_help(table, group) result(text)
      type(parameter_t), intent(in) :: table(:)
      character(len=*), intent(in) :: group
      character(len=:), allocatable :: text, value
      character(len=*), parameter :: nl = new_line('a')
      integer :: i
      text = ''
      do i = 1, size(table)
         if (table(i)%group /= group) cycle
         associate (p => table(i))
            value = format_value(p)
            if (p%type == type_real .and. len(value) > 0) value = short_number(p%real_value)
            if (len(value) == 0) value = merge('(none) ', '(unset)', p%type == type_real_list)
            value = trim(value)
            text = text//'    '//trim(p%name)//' = '//value//': '//trim(p%help)//nl//'        allowed: '// &
                   allowed_text(p)
            if (len_trim(p%sweep_list) > 0) then
               text = text//'; swept by &sweep '//trim(p%sweep_list)
               if (len_trim(p%sweep_alias) > 0) text = text//' (or its former name '//trim(p%sweep_alias)//')'
            end if
            if (len_trim(p%kinds) > 0) text = text//'; kind '//trim(p%kinds)//' only'
            text = text//nl
         end associate
      end do
   end function parameter_help
end module mpm_registry
