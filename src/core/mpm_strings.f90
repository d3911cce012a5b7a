!> Small text helpers for messages: numbers to strings (exact, or with a few significant digits for
!> a person to read), plurals, lower case.
module mpm_strings
   use mpm_kinds, only: dp, i8
   implicit none
   private
   public :: str, lower, num, num_at_least, num_at_most, plural, readable_numbers

   !> `str(x)`: the shortest usual text of an integer or real (g0 format).
   interface str
      module procedure str_int, str_int8, str_real
   end interface str

contains

   function str_int(value) result(text)
      integer, intent(in) :: value
      character(len=:), allocatable :: text
      character(len=16) :: buffer
      write (buffer, '(i0)') value
      text = trim(buffer)
   end function str_int

   function str_int8(value) result(text)
      integer(i8), intent(in) :: value
      character(len=:), allocatable :: text
      character(len=24) :: buffer
      write (buffer, '(i0)') value
      text = trim(buffer)
   end function str_int8

   function str_real(value) result(text)
      real(dp), intent(in) :: value
      character(len=:), allocatable :: text
      character(len=40) :: buffer
      write (buffer, '(g0)') value
      text = trim(adjustl(buffer))
   end function str_real

   !> `x` with `digits` significant digits (default 4) as a person reads it: 0.1611, 27.89, 10,
   !> 2.47e-05, 6.07e+07 (exponent form below 0.01 and from 1e5 on); trailing zeros dropped.
   function num(x, digits) result(text)
      real(dp), intent(in) :: x
      integer, intent(in), optional :: digits
      character(len=:), allocatable :: text
      character(len=48) :: buffer, form
      integer :: d, decimals, e
      d = 4
      if (present(digits)) d = max(1, min(digits, 17))
      if (x /= x) then
         text = 'NaN'
         return
      else if (abs(x) > huge(x)) then
         text = merge('Infinity ', '-Infinity', x > 0)
         text = trim(text)
         return
      else if (x == 0) then
         text = '0'
         return
      end if
      if (abs(x) >= 0.01_dp .and. abs(x) < 1.0e5_dp) then
         decimals = max(0, d - 1 - floor(log10(abs(x))))
         write (form, '("(f0.",i0,")")') decimals
         write (buffer, form) x
         text = trim(adjustl(buffer))
         if (index(text, '.') > 0) text = strip_zeros(text)
         if (text(1:1) == '.') text = '0'//text
         if (text(1:min(2, len(text))) == '-.') text = '-0'//text(2:)
         ! rounding may reach the exponent form's range (99999.5 -> 100000): keep the digits anyway
      else
         write (form, '("(es",i0,".",i0,"e3)")') d + 12, d - 1
         write (buffer, form) x
         text = trim(adjustl(buffer))
         e = index(text, 'E')
         read (text(e + 1:), *) decimals
         write (form, '(sp,i0.2)') decimals
         text = strip_zeros(text(1:e - 1))//'e'//trim(adjustl(form))
      end if
   contains
      function strip_zeros(mantissa) result(short)
         character(len=*), intent(in) :: mantissa
         character(len=:), allocatable :: short
         integer :: last
         short = mantissa
         if (index(short, '.') == 0) return
         last = len(short)
         do while (short(last:last) == '0')
            last = last - 1
         end do
         if (short(last:last) == '.') last = last - 1
         short = short(1:last)
      end function strip_zeros
   end function num

   !> num(x, digits) rounded up: a text of that many significant digits whose value is at least x (an
   !> allowed lower bound said in a message is one the input may take: x = 0.12500000001 reads 0.1251,
   !> not 0.125, which would be refused).
   function num_at_least(x, digits) result(text)
      real(dp), intent(in) :: x
      integer, intent(in), optional :: digits
      character(len=:), allocatable :: text
      text = bound_text(x, 1.0_dp, digits)
   end function num_at_least

   !> num(x, digits) rounded down: a text whose value is at most x (an allowed upper bound).
   function num_at_most(x, digits) result(text)
      real(dp), intent(in) :: x
      integer, intent(in), optional :: digits
      character(len=:), allocatable :: text
      text = bound_text(x, -1.0_dp, digits)
   end function num_at_most

   !> num(x, digits) moved by half a unit of its last digit at a time in direction `towards` (+1 up,
   !> -1 down) until its value is x or past it.
   function bound_text(x, towards, digits) result(text)
      real(dp), intent(in) :: x, towards
      integer, intent(in), optional :: digits
      character(len=:), allocatable :: text
      real(dp) :: shown, half_unit
      integer :: d, k, stat
      d = 4
      if (present(digits)) d = max(1, min(digits, 17))
      text = num(x, d)
      if (.not. (abs(x) <= huge(x)) .or. x == 0) return
      half_unit = 0.5_dp*10.0_dp**(floor(log10(abs(x))) + 1 - d)
      do k = 1, 4
         read (text, *, iostat=stat) shown
         if (stat /= 0) return
         if (towards*(shown - x) >= 0) return
         text = num(x + towards*k*half_unit, d)
      end do
   end function bound_text

   !> "1 case", "2 cases": `n` and `word` in the singular or with an s.
   function plural(n, word) result(text)
      integer, intent(in) :: n
      character(len=*), intent(in) :: word
      character(len=:), allocatable :: text
      text = str_int(n)//' '//word
      if (n /= 1) text = text//'s'
   end function plural

   !> `text` with every real number in it (a numeral with a point or an exponent, as str writes
   !> them) rewritten by num with `digits` significant digits; integers and words stay as they are.
   !> For messages made for files (full precision) shown on a terminal.
   function readable_numbers(text, digits) result(out)
      character(len=*), intent(in) :: text
      integer, intent(in), optional :: digits
      character(len=:), allocatable :: out
      integer :: i, j, stat
      real(dp) :: x
      logical :: is_real
      out = ''
      i = 1
      do while (i <= len(text))
         if (index('0123456789', text(i:i)) > 0 .and. .not. after_word(i)) then
            j = i
            is_real = .false.
            do while (j <= len(text))
               if (index('0123456789', text(j:j)) > 0) then
                  j = j + 1
               else if (text(j:j) == '.' .and. j < len(text)) then
                  if (index('0123456789', text(j + 1:j + 1)) == 0) exit
                  is_real = .true.
                  j = j + 1
               else if (index('eE', text(j:j)) > 0 .and. j < len(text)) then
                  if (index('+-0123456789', text(j + 1:j + 1)) == 0) exit
                  is_real = .true.
                  j = j + 2
               else
                  exit
               end if
            end do
            if (is_real) then
               read (text(i:j - 1), *, iostat=stat) x
               if (stat == 0) then
                  out = out//num(x, digits)
               else
                  out = out//text(i:j - 1)
               end if
            else
               out = out//text(i:j - 1)
            end if
            i = j
         else
            out = out//text(i:i)
            i = i + 1
         end if
      end do
   contains
      !> Is position k inside a word (a letter, digit or underscore before it), as in 'u_cm2'?
      logical function after_word(k)
         integer, intent(in) :: k
         after_word = .false.
         if (k > 1) after_word = verify(text(k - 1:k - 1), &
                                        'abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ_0123456789') == 0
      end function after_word
   end function readable_numbers

   !> ASCII lower case.
   pure function lower(text) result(low)
      character(len=*), intent(in) :: text
      character(len=len(text)) :: low
      integer :: i, code
      low = text
      do i = 1, len(text)
         code = iachar(text(i:i))
         if (code >= iachar('A') .and. code <= iachar('Z')) low(i:i) = achar(code + 32)
      end do
   end function lower
end module mpm_strings
