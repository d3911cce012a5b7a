!> The parameter registry: one table entry per input variable (group, name, type, allowed range,
!> unit, help line, sweep list name, /config attribute name) bound by pointer to the field it fills,
!> and everything that works from such a table: setting a variable from the text of its values as
!> the namelist reader (mpm_namelist) read them, from a file or a command-line override
!> `group.name=value`; range checks that name group, variable, value and range (and the known name
!> nearest to a misspelled one); the text of the echo, of --help and of the machine-readable
!> listing the Python loader reads. The reader's types and procedures are public here too.
!>
!> A table is built on one instance of the type it describes (`config_parameters` in mpm_config,
!> `sweep_parameters` in mpm_sweep) and lives only as long as that instance stays in place.
module mpm_registry
   use, intrinsic :: ieee_arithmetic, only: ieee_is_finite
   use mpm_kinds, only: dp, i8
   use mpm_errors, only: error_t, set_error, append_error
   use mpm_strings, only: str, lower, num
   use mpm_namelist, only: nml_value_t, nml_item_t, read_namelist, parse_namelist, read_input_text, add_overrides, &
                           item_place
   use mpm_suggest, only: did_you_mean, nearest_words, printable
   implicit none
   private
   public :: parameter_t, nml_value_t, nml_item_t
   public :: real_entry, int_entry, text_entry, logical_entry, real_list_entry
   public :: type_real, type_int, type_text, type_logical, type_real_list, type_name
   public :: read_namelist, parse_namelist, read_input_text, add_overrides, item_place
   public :: apply_items, set_parameter, check_parameter, in_list, allowed_text
   public :: value_list_t, read_value_list, single_value_list, set_from_list, list_text
   public :: format_value, same_value, quoted, real_value, int_value, text_value, find_parameter, group_namelist
   public :: parameter_listing, parameter_help, short_number, entry_names, used_by, for_kinds, sweep_name_hint
   public :: for_value, applies, place

   integer, parameter :: type_real = 1, type_int = 2, type_text = 3, type_logical = 4, type_real_list = 5

   !> One input variable: what it is, what it may be, and where its value lives.
   type :: parameter_t
      character(len=16) :: group = ''
      character(len=32) :: name = ''
      !> Name of its /config attribute and /cases column (usually `name`).
      character(len=32) :: attribute = ''
      integer :: type = type_real
      character(len=16) :: unit = ''
      character(len=480) :: help = ''
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
      !> Used only when text variable `needs_variable` of the same table is `needs_word` ('' = always):
      !> given otherwise it is refused, and it is left out of the echo (see for_value, applies).
      character(len=32) :: needs_variable = ''
      character(len=16) :: needs_word = ''
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

   !> A number as short as it reads (ranges and defaults in messages and --help): 0, 10, 0.5, 2e+11, NaN, Infinity.
   function short_number(x) result(text)
      real(dp), intent(in) :: x
      character(len=:), allocatable :: text
      character(len=32) :: buffer
      integer :: e, k
      if (x /= x .or. abs(x) > huge(x)) then  ! (no number, no exponent to shorten: NaN, Infinity)
         text = num(x)
         return
      end if
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
      word_allowed = len_trim(word) > 0
      if (len_trim(p%words) > 0 .and. word_allowed) word_allowed = in_list(word, p%words)
   end function word_allowed

   !> Is `word` one of the comma-separated `list` (blanks around an item and trailing blanks of `word` do
   !> not count; an empty word is none)? Compared in place: building the list without blanks for one
   !> index() was 0.2 % of the paper's Table-2 sweeps, whose every case is checked.
   pure logical function in_list(word, list)
      character(len=*), intent(in) :: word, list
      integer :: first, last, n
      in_list = .false.
      if (len_trim(word) == 0) return
      n = len_trim(list)
      first = 1
      do while (first <= n)
         last = index(list(first:n), ',')
         last = merge(n, first + last - 2, last == 0)
         do while (first < last .and. list(first:first) == ' ')
            first = first + 1
         end do
         if (list(first:last) == word) then
            in_list = .true.
            return
         end if
         first = last + 2
      end do
   end function in_list

   !> Check the bound value of `p` against its range; `where` prefixes the message (e.g. "file:3: ").
   subroutine check_parameter(p, error, where)
      type(parameter_t), intent(in) :: p
      type(error_t), allocatable, intent(inout) :: error
      character(len=*), intent(in), optional :: where
      character(len=:), allocatable :: hint
      integer :: k
      select case (p%type)
      case (type_real)
         if (.not. has_value(p)) return ! an optional variable not given
         if (.not. real_in_range(p, p%real_value)) call out_of_range(plain(p%real_value), trim(p%name), p%real_value)
      case (type_int)
         if (.not. real_in_range(p, real(p%int_value, dp))) call out_of_range(str(p%int_value), trim(p%name), 1.0_dp)
      case (type_text)
         if (.not. word_allowed(p, p%text_value)) then
            if (len_trim(p%words) > 0) then
               hint = did_you_mean(trim(p%text_value), trim(p%words), "'", "'")
               if (len(hint) == 0) hint = ';'
               call append_error(error, prefix()//trim(p%group)//": "//trim(p%name)//" = "// &
                                 quoted(printable(trim(p%text_value)))//" is unknown"//hint//" allowed: "//allowed_text(p))
            else
               call append_error(error, prefix()//trim(p%group)//": "//trim(p%name)//" is empty; allowed: "// &
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
         call append_error(error, prefix()//trim(p%group)//": "//label//" = "//value//" is out of range"//why// &
                           "; allowed: "//allowed_text(p))
      end subroutine out_of_range
      !> `where`, or '' (formed for a message only: a value in range costs no allocation)
      function prefix() result(text)
         character(len=:), allocatable :: text
         text = ''
         if (present(where)) text = where
      end function prefix
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
      if (index(value%text, achar(0)) > 0) then ! (a file name would end there)
         problem = quoted(printable(value%text))//' holds a NUL byte (\0, character code 0), where a program '// &
                   'reading it would see the text end'
         return
      end if
      if (p%type == type_text) then
         if (.not. value%quoted) then
            problem = printable(value%text)//' is not quoted text'
         else if (len(value%text) > len(p%text_value)) then
            problem = quoted(printable(value%text))//' is longer than '//str(len(p%text_value))//' characters'
         end if
         return
      end if
      if (value%quoted) then
         problem = quoted(printable(value%text))//' is text, not '//article(type_name(p%type))
         return
      end if
      word = lower(value%text)
      select case (p%type)
      case (type_logical)
         select case (word)
         case ('t', 'f', '.t.', '.f.', '.true.', '.false.', 'true', 'false', '.t', '.f')
         case default
            problem = printable(value%text)//' is not a logical'
         end select
      case (type_int)
         if (verify(word(1:1), '+-0123456789') /= 0 .or. verify(word(2:), '0123456789') /= 0 .or. &
             verify(word, '+-') == 0) then
            problem = printable(value%text)//' is not a whole number'
         else
            read (word, *, iostat=stat) big
            if (stat /= 0 .or. len(word) > 19 .or. abs(big) > huge(1)) &
               problem = printable(value%text)//' is beyond the integers of this program (at most '//str(huge(1))//')'
         end if
      case default ! real
         select case (word)
         case ('nan', 'inf', '+inf', '-inf', 'infinity', '+infinity', '-infinity')
         case default
            if (verify(word, '+-0123456789.ed') /= 0 .or. scan(word, '0123456789') == 0) then
               problem = printable(value%text)//' is not a real number'
            else
               block
                  real(dp) :: x
                  read (word, *, iostat=stat) x
               end block
               if (stat /= 0) problem = printable(value%text)//' is not a real number'
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
            call append_error(error, where//"group &"//group//": unknown variable '"//printable(items(i)%name)// &
                              "'"//unknown_variable_hint(table, items(i), group, where))
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

   !> What follows "unknown variable 'name'" of the &sweep group, whose names are `names` (its lists
   !> and settings, comma separated): a variable of the run's `table` that is not swept is named as
   !> such, else the names near it; then the names.
   function sweep_name_hint(name, names, table) result(text)
      character(len=*), intent(in) :: name, names
      type(parameter_t), intent(in) :: table(:)
      character(len=:), allocatable :: text
      integer :: k
      do k = 1, size(table)
         if (table(k)%name /= name) cycle
         text = "; '"//name//"' of &"//trim(table(k)%group)//" is not swept (no &sweep list varies it); "// &
                "allowed names: "//names
         return
      end do
      text = did_you_mean(name, names, "'", "'")
      if (len(text) == 0) text = ';'
      text = text//" allowed names: "//names
   end function sweep_name_hint

   !> What follows "unknown variable 'name'" of `group`: the group it belongs to when another group has
   !> it (an override is shown as it should be typed), or the names of `group` near it; then the names
   !> `group` has.
   function unknown_variable_hint(table, item, group, where) result(text)
      type(parameter_t), intent(in) :: table(:)
      type(nml_item_t), intent(in) :: item
      character(len=*), intent(in) :: group, where
      character(len=:), allocatable :: text, names, others, near
      integer :: k, eq
      text = ''
      names = entry_names(table, group)
      do k = 1, size(table)
         if (table(k)%group == group .or. table(k)%name /= item%name) cycle
         text = "; it belongs to &"//trim(table(k)%group)
         if (allocated(item%origin)) then ! as the override should have been typed
            eq = index(where, '=')
            if (eq > 0) text = text//": "//trim(table(k)%group)//"."//trim(table(k)%name)//where(eq:len(where) - 3)
         end if
         text = text//" (allowed names in &"//group//": "//names//")"
         return
      end do
      near = did_you_mean(item%name, names, "'", "'")
      if (len(near) == 0) then
         others = ''
         do k = 1, size(table)
            if (table(k)%group == group) cycle
            if (len(others) > 0) others = others//', '
            others = others//trim(table(k)%name)
         end do
         near = nearest_words(item%name, others)
         if (index(near, ',') > 0) near = near(1:index(near, ',') - 1)
         do k = 1, size(table)
            if (len(near) == 0) exit
            if (table(k)%group == group .or. table(k)%name /= near) cycle
            near = "; did you mean '"//near//"' of &"//trim(table(k)%group)//"?"
            exit
         end do
      end if
      if (len(near) > 0) then
         text = near//" allowed names: "//names
      else
         text = "; allowed names: "//names
      end if
   end function unknown_variable_hint

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

   !> Do entries `p` and `q` (of one variable) hold the same value bit for bit? Then their
   !> format_value texts are equal; .false. says only that they may differ (compare format_value).
   !> Comparing a sweep's every case with the defaults this way saves formatting (0.4 % of the paper's
   !> Table-2 sweeps).
   pure logical function same_value(p, q)
      type(parameter_t), intent(in) :: p, q
      integer :: k
      same_value = .false.
      if (p%type /= q%type) return
      select case (p%type)
      case (type_real)
         if (has_value(p) .neqv. has_value(q)) return
         same_value = .not. has_value(p)
         if (.not. same_value) same_value = transfer(p%real_value, 0_i8) == transfer(q%real_value, 0_i8)
      case (type_int)
         same_value = p%int_value == q%int_value
      case (type_logical)
         same_value = p%logical_value .eqv. q%logical_value
      case (type_text)
         same_value = trim(p%text_value) == trim(q%text_value)
      case default
         if (p%list_count /= q%list_count) return
         same_value = .true.
         do k = 1, p%list_count
            if (transfer(p%list_value(k), 0_i8) /= transfer(q%list_value(k), 0_i8)) same_value = .false.
         end do
      end select
   end function same_value

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
      used_by = len_trim(p%kinds) == 0 .or. in_list(kind, p%kinds)
   end function used_by

   !> Where variable `name` of `group` was given ("file:line: "), '' when `given` (the table the input was
   !> read into) does not say: the prefix of a message that blames that variable.
   function place(given, group, name) result(prefix)
      type(parameter_t), intent(in), optional :: given(:)
      character(len=*), intent(in) :: group, name
      character(len=:), allocatable :: prefix
      integer :: k
      prefix = ''
      if (.not. present(given)) return
      k = find_parameter(given, group, name)
      if (k == 0) return
      if (given(k)%line > 0) prefix = trim(given(k)%origin)//' '
   end function place

   !> `p` restricted to the scene kinds `kinds` (comma separated), for the table's constructors.
   function for_kinds(p, kinds) result(q)
      type(parameter_t), intent(in) :: p
      character(len=*), intent(in) :: kinds
      type(parameter_t) :: q
      q = p
      q%kinds = kinds
   end function for_kinds

   !> `p` used only when text variable `variable` of its table is `word` (flip_fraction: transfer = 'blend').
   function for_value(p, variable, word) result(q)
      type(parameter_t), intent(in) :: p
      character(len=*), intent(in) :: variable, word
      type(parameter_t) :: q
      q = p
      q%needs_variable = variable
      q%needs_word = word
   end function for_value

   !> Does entry `k` of `table` apply: has it no condition, or does the variable it needs have its word?
   logical function applies(table, k)
      type(parameter_t), intent(in) :: table(:)
      integer, intent(in) :: k
      integer :: i
      applies = .true.
      if (len_trim(table(k)%needs_variable) == 0) return
      do i = 1, size(table)
         if (table(i)%name /= table(k)%needs_variable .or. table(i)%type /= type_text) cycle
         applies = trim(table(i)%text_value) == trim(table(k)%needs_word)
         return
      end do
   end function applies

   !> `&group name=value, ... /` for every variable of `group` that has a value and applies (and, when
   !> `kind` is given, that scene kind uses).
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
         if (.not. applies(table, i)) cycle
         value = format_value(table(i))
         if (len(value) == 0) cycle
         if (text /= '&'//group) text = text//','
         text = text//' '//trim(table(i)%name)//'='//value
      end do
      text = text//' /'
   end function group_namelist

   !> The table as tab-separated lines with a header: group, name, attribute, type, unit, value,
   !> allowed, sweep list, its former name, help, the scene kinds that use it ('' = every kind).
   !> Read by the Python loader (postprocess/mpm1d_post/loader.py) and the namelist reference's generator.
   function parameter_listing(table) result(text)
      type(parameter_t), intent(in) :: table(:)
      character(len=:), allocatable :: text
      character(len=*), parameter :: tab = achar(9), nl = new_line('a')
      integer :: i
      text = 'group'//tab//'name'//tab//'attribute'//tab//'type'//tab//'unit'//tab//'value'//tab//'allowed'// &
             tab//'sweep_list'//tab//'sweep_alias'//tab//'help'//tab//'kinds'
      do i = 1, size(table)
         associate (p => table(i))
            text = text//nl//trim(p%group)//tab//trim(p%name)//tab//trim(p%attribute)//tab//type_name(p%type)// &
                   tab//trim(p%unit)//tab//format_value(p)//tab//allowed_text(p)//tab//trim(p%sweep_list)//tab// &
                   trim(p%sweep_alias)//tab//trim(p%help)//tab//trim(p%kinds)
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
            if (len_trim(p%needs_variable) > 0) text = text//'; '//trim(p%needs_variable)//" = '"// &
                                                       trim(p%needs_word)//"' only"
            text = text//nl
         end associate
      end do
   end function parameter_help
end module mpm_registry
