!> mpm1d's namelist reader: the text of an input (a file, standard input or a FIFO, read once) into
!> assignments `name = value, value, ...` by group, with the line of each, and command-line overrides
!> `group.name=value` read the same way. The syntax: groups `&name ... /` (or `&end`) over any number
!> of lines, quoted text ('...' or "...", a quote doubled inside), unquoted numbers and logicals,
!> repeat counts `r*value`, empty values between commas, comments after `!`. Refused, with file and
!> line: text outside a group, a group without its '/', a value without a name, indexed assignments,
!> a text that runs past the end of its line; an input in UTF-16 or with a byte-order mark is named
!> as such, and control characters in what a message quotes are shown escaped (\0 for NUL).
!> What the values mean is the registry's business (mpm_registry): this module only reads them.
module mpm_namelist
   use mpm_errors, only: error_t, set_error, append_error
   use mpm_strings, only: str, lower
   use mpm_kinds, only: dp
   use mpm_suggest, only: did_you_mean, printable
   use mpm_files, only: absolute_path
   implicit none
   private
   public :: nml_value_t, nml_item_t
   public :: read_namelist, parse_namelist, read_input_text, add_overrides, item_place

   character(len=*), parameter :: identifier_characters = &
                                  'abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789_'
   character(len=*), parameter :: letters = 'abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ'
   !> Past this many problems reading stops (the rest of a binary or garbage file adds nothing).
   integer, parameter :: max_problems = 100

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

   !> The state of one reading: the text and where the reader is in it, the group and assignment being
   !> read, and what has been read so far (storage doubled when full, trimmed at the end, so that
   !> 100,000 values or 20,000 assignments are read in linear time).
   type :: reader_t
      character(len=:), allocatable :: text, path, group
      !> line_of(k): the line of character k.
      integer, allocatable :: line_of(:)
      integer :: pos = 1
      integer :: group_line = 0
      !> The assignment being read: its values so far, and whether the last token was a value.
      type(nml_item_t) :: item
      integer :: nvalues = 0
      logical :: have_item = .false., after_value = .false.
      type(nml_item_t), allocatable :: items(:)
      integer :: nitems = 0
      character(len=32), allocatable :: groups(:)
      integer, allocatable :: group_lines(:)
      type(error_t), allocatable :: error
   contains
      procedure :: start, refuse_encoding, next_group, read_group, group_ends, start_assignment, read_value
      procedure :: next_value, quoted_text, token_text, skip_token, repeat_star, add_value, finish_item, finish
      procedure :: skip_line, skip_blanks_and_comments, identifier, assignment_ahead, end_marker, quote_at
      procedure :: where, line_text, too_many, problem
   end type reader_t

contains

   ! ------------------------------------------------------------------ reading a namelist

   !> Parse namelist `text` (from `source`, named in messages as "source:line: ") into assignments;
   !> `groups` receives the group names in the order given, `group_lines` their lines. Problems of
   !> syntax do not stop the reading: every one is reported at once. Also the way for other text to
   !> reach the registry, e.g. a command-line override `group.name=value` read as "&group name=value /".
   subroutine parse_namelist(text, source, items, groups, group_lines, error)
      character(len=*), intent(in) :: text, source
      type(nml_item_t), allocatable, intent(out) :: items(:)
      character(len=32), allocatable, intent(out) :: groups(:)
      integer, allocatable, intent(out) :: group_lines(:)
      type(error_t), allocatable, intent(out) :: error
      type(reader_t) :: reader

      call reader%start(text, source)
      if (.not. reader%refuse_encoding()) then
         do while (reader%next_group())
            call reader%read_group()
         end do
      end if
      call reader%finish(items, groups, group_lines, error)
   end subroutine parse_namelist

   !> Read every group of file `path` into assignments (parse_namelist of its text).
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

   !> A reader at the start of `text`, with the line of every character.
   subroutine start(self, text, source)
      class(reader_t), intent(inout) :: self
      character(len=*), intent(in) :: text, source
      integer :: k
      self%text = text
      self%path = source
      allocate (self%items(0), self%groups(0), self%group_lines(0))
      allocate (self%line_of(len(text) + 1))
      self%line_of(1) = 1
      do k = 2, len(text) + 1
         self%line_of(k) = self%line_of(k - 1)
         if (text(k - 1:k - 1) == new_line('a')) self%line_of(k) = self%line_of(k) + 1
      end do
      self%pos = 1
   end subroutine start

   !> An encoding the reader does not take, named as such: UTF-16 (by its byte-order mark, or by NUL
   !> bytes between ASCII characters) stops the reading (true); a UTF-8 byte-order mark is reported
   !> and skipped, so that the rest of the input is read and checked too.
   logical function refuse_encoding(self) result(refused)
      class(reader_t), intent(inout) :: self
      character(len=*), parameter :: convert = ' (convert it, e.g. iconv -f UTF-16 -t UTF-8 FILE > NEW)'
      character(len=:), allocatable :: head
      integer :: n, k, odd_zeros, even_zeros
      refused = .false.
      head = self%text(1:min(len(self%text), 3))
      if (len(head) >= 2) then
         if (head(1:2) == char(255)//char(254) .or. head(1:2) == char(254)//char(255)) then
            call self%problem(self%path//":1: the input is UTF-16 text (it starts with the byte-order mark "// &
                              merge('FF FE', 'FE FF', head(1:1) == char(255))//"); allowed: ASCII or UTF-8 text"// &
                              convert)
            refused = .true.
            return
         end if
      end if
      ! UTF-16 without a mark: ASCII characters, each beside a NUL byte (on the same side each time)
      n = min(len(self%text), 64)
      odd_zeros = 0
      even_zeros = 0
      do k = 1, n
         if (self%text(k:k) /= achar(0)) cycle
         if (mod(k, 2) == 1) odd_zeros = odd_zeros + 1
         if (mod(k, 2) == 0) even_zeros = even_zeros + 1
      end do
      if (n >= 4 .and. ((odd_zeros >= n/2 - 1 .and. even_zeros == 0) .or. (even_zeros >= n/2 - 1 .and. &
                                                                            odd_zeros == 0))) then
         call self%problem(self%path//":1: the input looks like UTF-16 text (a NUL byte beside each character); "// &
                           "allowed: ASCII or UTF-8 text"//convert)
         refused = .true.
         return
      end if
      if (head == char(239)//char(187)//char(191)) then
         call self%problem(self%path//":1: the input starts with a UTF-8 byte-order mark (bytes EF BB BF); "// &
                           "allowed: text without one (an editor's 'UTF-8 without BOM', or sed -i '1s/^"// &
                           "\xEF\xBB\xBF//' FILE)")
         self%pos = 4
      end if
   end function refuse_encoding

   !> Move to the next group and read its name: true when there is one to read. Text outside a group
   !> and a '&' without a name are reported, and their lines skipped.
   logical function next_group(self) result(found)
      class(reader_t), intent(inout) :: self
      found = .false.
      do
         call self%skip_blanks_and_comments()
         if (self%pos > len(self%text) .or. self%too_many()) return
         if (self%text(self%pos:self%pos) /= '&') then
            call self%problem(self%where(self%pos)//"text outside a namelist group: '"// &
                              self%line_text(self%pos)//"; allowed: &group name=value, ... / and comments after '!'")
            call self%skip_line()
            cycle
         end if
         self%group_line = self%line_of(self%pos)
         self%pos = self%pos + 1
         self%group = lower(self%identifier())
         if (len(self%group) == 0) then
            call self%problem(self%where(self%pos)//"'&' without a group name")
            call self%skip_line()
            cycle
         end if
         if (any(self%groups == self%group)) call self%problem(self%path//":"//str(self%group_line)// &
                                                                ": group &"//self%group//" is given twice")
         self%groups = [character(len=32) :: self%groups, self%group]
         self%group_lines = [self%group_lines, self%group_line]
         found = .true.
         return
      end do
   end function next_group

   !> The body of a group: assignments and their values, up to the group's end.
   subroutine read_group(self)
      class(reader_t), intent(inout) :: self
      self%have_item = .false.
      self%after_value = .false.
      do
         call self%skip_blanks_and_comments()
         if (self%too_many()) return
         if (self%group_ends()) then
            call self%finish_item()
            return
         end if
         if (self%text(self%pos:self%pos) == ',') then
            ! a comma after a comma (or after the '='): an empty value
            if (.not. self%after_value .and. self%have_item) call self%add_value(nml_value_t(text='', null=.true.))
            self%after_value = .false.
            self%pos = self%pos + 1
         else if (self%assignment_ahead()) then
            call self%start_assignment()
         else if (.not. self%have_item) then
            call self%problem(self%where(self%pos)//"group &"//self%group//": value '"// &
                              printable(self%token_text())//"' without a name; allowed: name = value")
            call self%skip_token()
         else
            call self%read_value()
         end if
      end do
   end subroutine read_group

   !> Does the group end at the reader's position? '/' or the older '&end' end it (and are passed);
   !> the end of the text or the next group's '&' end it too, reported as a missing '/'.
   logical function group_ends(self) result(ends)
      class(reader_t), intent(inout) :: self
      ends = .true.
      if (self%pos > len(self%text)) then
         call self%problem(self%path//":"//str(self%group_line)//": group &"//self%group// &
                           ": not terminated by '/' (end of file reached)")
      else if (self%text(self%pos:self%pos) == '/') then
         self%pos = self%pos + 1
      else if (self%end_marker()) then
         self%pos = self%pos + 4
      else if (self%text(self%pos:self%pos) == '&') then
         call self%problem(self%where(self%pos)//"group &"//self%group//": not terminated by '/' before the next group")
      else
         ends = .false.
      end if
   end function group_ends

   !> `name =` (or the refused `name(...) =`) starts the next assignment.
   subroutine start_assignment(self)
      class(reader_t), intent(inout) :: self
      call self%finish_item()
      self%item%group = self%group
      self%item%line = self%line_of(self%pos)
      self%item%name = lower(self%identifier())
      allocate (self%item%values(0))
      self%nvalues = 0
      call self%skip_blanks_and_comments()
      if (self%text(self%pos:self%pos) == '(') then
         call self%problem(self%where(self%pos)//"group &"//self%group//": '"//self%item%name// &
                           "(...)': indexed assignment is not supported; give the whole list")
         do while (self%pos <= len(self%text))
            if (self%text(self%pos:self%pos) == '=') exit
            self%pos = self%pos + 1
         end do
      end if
      self%pos = self%pos + 1 ! the '='
      self%have_item = .true.
      self%after_value = .false.
   end subroutine start_assignment

   !> One value of the current assignment, maybe with a repeat count `r*` (r times the value; `r*`
   !> alone: r empty values).
   subroutine read_value(self)
      class(reader_t), intent(inout) :: self
      type(nml_value_t) :: value
      integer :: repeat, stat, star, k
      repeat = 1
      star = 0
      if (.not. self%quote_at(self%pos)) star = self%repeat_star()
      if (star > 0) then
         read (self%text(self%pos:star - 1), *, iostat=stat) repeat
         if (stat /= 0 .or. repeat < 1 .or. repeat > 100000) then
            call self%problem(self%where(self%pos)//"group &"//self%group//": bad repeat count '"// &
                              self%text(self%pos:star - 1)//"' for '"//self%item%name//"'")
            repeat = 1
         end if
         self%pos = star + 1
         value = nml_value_t(text='', null=.true.)
         if (self%pos <= len(self%text)) then
            if (.not. (blank(self%text(self%pos:self%pos)) .or. self%text(self%pos:self%pos) == ',' .or. &
                       self%text(self%pos:self%pos) == '/')) value = self%next_value()
         end if
      else
         value = self%next_value()
      end if
      do k = 1, repeat
         call self%add_value(value)
      end do
      self%after_value = .true.
   end subroutine read_value

   !> The value at the reader's position: quoted text, or a token up to a blank, ',', '/', '!' or '&'.
   function next_value(self) result(value)
      class(reader_t), intent(inout) :: self
      type(nml_value_t) :: value
      if (self%quote_at(self%pos)) then
         value%quoted = .true.
         value%text = self%quoted_text()
      else
         value%text = self%token_text()
         call self%skip_token()
      end if
   end function next_value

   !> Quoted text at the reader's position, without its quotes (a doubled quote is one quote). No text
   !> spans lines: a line break before the closing quote is reported.
   function quoted_text(self) result(text)
      class(reader_t), intent(inout) :: self
      character(len=:), allocatable :: text
      character(len=1) :: quote
      quote = self%text(self%pos:self%pos)
      text = ''
      self%pos = self%pos + 1
      do
         if (self%pos > len(self%text)) then
            call self%problem(self%where(self%pos)//"group &"//self%group//": text for '"//self%item%name// &
                              "' has no closing quote")
            return
         end if
         if (self%text(self%pos:self%pos) == new_line('a')) then
            call self%problem(self%where(self%pos)//"group &"//self%group//": text for '"//self%item%name// &
                              "' runs past the end of its line (a closing quote missing, or a line break "// &
                              "in the text); allowed: quoted text on one line")
            return
         end if
         if (self%text(self%pos:self%pos) == quote) then
            if (self%pos < len(self%text)) then
               if (self%text(self%pos + 1:self%pos + 1) == quote) then
                  text = text//quote
                  self%pos = self%pos + 2
                  cycle
               end if
            end if
            self%pos = self%pos + 1
            return
         end if
         text = text//self%text(self%pos:self%pos)
         self%pos = self%pos + 1
      end do
   end function quoted_text

   function token_text(self) result(token)
      class(reader_t), intent(in) :: self
      character(len=:), allocatable :: token
      integer :: k
      k = self%pos
      do while (k <= len(self%text))
         if (blank(self%text(k:k)) .or. index(',/!&', self%text(k:k)) > 0) exit
         k = k + 1
      end do
      token = self%text(self%pos:k - 1)
   end function token_text

   subroutine skip_token(self)
      class(reader_t), intent(inout) :: self
      self%pos = self%pos + max(len(self%token_text()), 1)
   end subroutine skip_token

   !> Position of the '*' of a repeat count `digits*` at the reader's position, 0 if none.
   integer function repeat_star(self)
      class(reader_t), intent(in) :: self
      integer :: k
      repeat_star = 0
      k = self%pos
      do while (k <= len(self%text))
         if (index('0123456789', self%text(k:k)) == 0) exit
         k = k + 1
      end do
      if (k > self%pos .and. k <= len(self%text)) then
         if (self%text(k:k) == '*') repeat_star = k
      end if
   end function repeat_star

   !> Append `value` to the current assignment's values (storage doubled when full).
   subroutine add_value(self, value)
      class(reader_t), intent(inout) :: self
      type(nml_value_t), intent(in) :: value
      type(nml_value_t), allocatable :: grown(:)
      if (self%nvalues == size(self%item%values)) then
         allocate (grown(max(8, 2*self%nvalues)))
         grown(1:self%nvalues) = self%item%values(1:self%nvalues)
         call move_alloc(grown, self%item%values)
      end if
      self%nvalues = self%nvalues + 1
      self%item%values(self%nvalues) = value
   end subroutine add_value

   !> The current assignment, if any, joins the items read (its values trimmed to those given).
   subroutine finish_item(self)
      class(reader_t), intent(inout) :: self
      type(nml_item_t), allocatable :: grown(:)
      if (allocated(self%item%values)) then
         self%item%values = self%item%values(1:self%nvalues)
         if (self%nitems == size(self%items)) then
            allocate (grown(max(8, 2*self%nitems)))
            grown(1:self%nitems) = self%items(1:self%nitems)
            call move_alloc(grown, self%items)
         end if
         self%nitems = self%nitems + 1
         self%items(self%nitems) = self%item
         deallocate (self%item%values)
      end if
      self%nvalues = 0
   end subroutine finish_item

   !> Hand over what was read.
   subroutine finish(self, items, groups, group_lines, error)
      class(reader_t), intent(inout) :: self
      type(nml_item_t), allocatable, intent(out) :: items(:)
      character(len=32), allocatable, intent(out) :: groups(:)
      integer, allocatable, intent(out) :: group_lines(:)
      type(error_t), allocatable, intent(out) :: error
      items = self%items(1:self%nitems)
      call move_alloc(self%groups, groups)
      call move_alloc(self%group_lines, group_lines)
      if (allocated(self%error)) call move_alloc(self%error, error)
   end subroutine finish

   ! ------------------------------------------------------------------ the reader's small steps

   subroutine skip_line(self)
      class(reader_t), intent(inout) :: self
      do while (self%pos <= len(self%text))
         if (self%text(self%pos:self%pos) == new_line('a')) exit
         self%pos = self%pos + 1
      end do
   end subroutine skip_line

   subroutine skip_blanks_and_comments(self)
      class(reader_t), intent(inout) :: self
      do while (self%pos <= len(self%text))
         if (self%text(self%pos:self%pos) == '!') then
            call self%skip_line()
         else if (blank(self%text(self%pos:self%pos))) then
            self%pos = self%pos + 1
         else
            exit
         end if
      end do
   end subroutine skip_blanks_and_comments

   function identifier(self) result(name)
      class(reader_t), intent(inout) :: self
      character(len=:), allocatable :: name
      integer :: first
      first = self%pos
      do while (self%pos <= len(self%text))
         if (index(identifier_characters, self%text(self%pos:self%pos)) == 0) exit
         self%pos = self%pos + 1
      end do
      name = self%text(first:self%pos - 1)
   end function identifier

   !> Is an identifier followed by '=' (or '(') at the reader's position? (the start of an assignment)
   logical function assignment_ahead(self)
      class(reader_t), intent(in) :: self
      integer :: k
      assignment_ahead = .false.
      k = self%pos
      if (index(letters, self%text(k:k)) == 0) return
      do while (k <= len(self%text))
         if (index(identifier_characters, self%text(k:k)) == 0) exit
         k = k + 1
      end do
      do while (k <= len(self%text))
         if (.not. blank(self%text(k:k))) exit
         k = k + 1
      end do
      if (k > len(self%text)) return
      assignment_ahead = self%text(k:k) == '=' .or. self%text(k:k) == '('
   end function assignment_ahead

   !> Is '&end' (not followed by a name character) at the reader's position?
   logical function end_marker(self)
      class(reader_t), intent(in) :: self
      end_marker = .false.
      if (self%pos + 3 > len(self%text)) return
      if (lower(self%text(self%pos:self%pos + 3)) /= '&end') return
      end_marker = .true.
      if (self%pos + 4 <= len(self%text)) end_marker = index(identifier_characters, self%text(self%pos + 4:self%pos + 4)) == 0
   end function end_marker

   logical function quote_at(self, k)
      class(reader_t), intent(in) :: self
      integer, intent(in) :: k
      quote_at = self%text(k:k) == "'" .or. self%text(k:k) == '"'
   end function quote_at

   !> "path:line: " of character `at`.
   function where(self, at) result(prefix)
      class(reader_t), intent(in) :: self
      integer, intent(in) :: at
      character(len=:), allocatable :: prefix
      prefix = self%path//":"//str(self%line_of(min(at, size(self%line_of))))//": "
   end function where

   !> Up to 60 characters of the line from `at`, control characters shown escaped, and a note when it
   !> holds NUL bytes (a binary file).
   function line_text(self, at) result(line)
      class(reader_t), intent(in) :: self
      integer, intent(in) :: at
      character(len=:), allocatable :: line
      integer :: last
      last = index(self%text(at:), new_line('a'))
      if (last == 0) then
         line = trim(self%text(at:min(len(self%text), at + 60)))
      else
         line = trim(self%text(at:min(at + last - 2, at + 60)))
      end if
      if (index(line, achar(0)) > 0) then
         line = printable(line)//"' (NUL bytes: not a text file?)"
      else
         line = printable(line)//"'"
      end if
   end function line_text

   logical function too_many(self)
      class(reader_t), intent(in) :: self
      too_many = .false.
      if (allocated(self%error)) too_many = self%error%problems > max_problems
   end function too_many

   subroutine problem(self, message)
      class(reader_t), intent(inout) :: self
      character(len=*), intent(in) :: message
      call append_error(self%error, message)
   end subroutine problem

   pure logical function blank(c)
      character(len=1), intent(in) :: c
      blank = c == ' ' .or. c == achar(9) .or. c == new_line('a') .or. c == achar(13)
   end function blank

   ! ------------------------------------------------------------------ input text and overrides

   !> The whole text of input file `path`, read once ('-': standard input, to its end). A FIFO or other
   !> stream (`mpm1d <(...)`) is read once to its end as standard input is: it cannot be read twice.
   subroutine read_input_text(path, text, error)
      use, intrinsic :: iso_fortran_env, only: input_unit
      use mpm_files, only: path_kind, path_other
      character(len=*), intent(in) :: path
      character(len=:), allocatable, intent(out) :: text
      type(error_t), allocatable, intent(out) :: error
      integer :: n, unit, stat, reason
      logical :: is_folder, stream
      character(len=:), allocatable :: looked
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
      if (stat /= 0) then ! (the compiler's message repeats the name: its reason alone, after the last "': ")
         reason = index(msg, "': ", back=.true.)
         looked = ''
         if (path(1:1) /= '/') looked = ' (looked for '//absolute_path(path)//', relative to the folder mpm1d runs in)'
         call set_error(error, "cannot open input file '"//trim(path)//"'"//looked//': '// &
                        trim(msg(merge(reason + 3, 1, reason > 0):)))
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
      integer :: i, j, dot, eq

      known = ''
      do i = 1, size(known_groups)
         if (i > 1) known = known//', '
         known = known//trim(known_groups(i))
      end do
      do i = 1, size(overrides)
         text = trim(overrides(i))
         origin = "command line '"//printable(text)//"'"
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
            call append_error(error, origin//": unknown namelist group '"//printable(group)//"'"// &
                              did_you_mean(group, known, "'", "'")//" (known groups: "//known//")")
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
      integer :: first, comma, stat
      real(dp) :: x
      if (scan(value, '"'//"'") > 0) then
         text = value
         return
      end if
      text = ''
      first = 1
      do
         comma = index(value(first:), ',')
         if (comma == 0) then
            word = trim(adjustl(value(first:)))
         else
            word = trim(adjustl(value(first:first + comma - 2)))
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
         first = first + comma
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
      integer :: k, first
      out = ''
      first = 1
      do
         k = index(text(first:), old)
         if (k == 0) exit
         out = out//text(first:first + k - 2)//new
         first = first + k - 1 + len(old)
      end do
      out = out//text(first:)
   end function replace_all
end module mpm_namelist
