!> "Did you mean ...?": the known words nearest to a misspelled one, and input text made printable
!> for messages. Nearness is the optimal string alignment distance: the fewest insertions, deletions,
!> substitutions and swaps of two adjacent characters that turn one word into the other (Levenshtein
!> distance with the transpositions of Damerau, Commun. ACM 7(3), 1964, doi:10.1145/363958.363994),
!> so that 'discretization' is one edit from 'discretisation' and 'shceme' one from 'scheme'.
module mpm_suggest
   implicit none
   private
   public :: edit_distance, nearest_words, did_you_mean, printable

   !> Most words a suggestion names (several known words at the same distance).
   integer, parameter :: max_suggestions = 3

contains

   !> The optimal string alignment distance between `a` and `b` (compared as given: lower both first
   !> for a case-insensitive comparison).
   pure integer function edit_distance(a, b) result(distance)
      character(len=*), intent(in) :: a, b
      integer :: d(0:len(a), 0:len(b))
      integer :: i, j, cost
      do i = 0, len(a)
         d(i, 0) = i
      end do
      do j = 0, len(b)
         d(0, j) = j
      end do
      do j = 1, len(b)
         do i = 1, len(a)
            cost = merge(0, 1, a(i:i) == b(j:j))
            d(i, j) = min(d(i - 1, j) + 1, d(i, j - 1) + 1, d(i - 1, j - 1) + cost)
            if (i > 1 .and. j > 1) then
               if (a(i:i) == b(j - 1:j - 1) .and. a(i - 1:i - 1) == b(j:j)) d(i, j) = min(d(i, j), d(i - 2, j - 2) + 1)
            end if
         end do
      end do
      distance = d(len(a), len(b))
   end function edit_distance

   !> The words of `words` (comma separated) nearest to `word`, comma separated in their order there:
   !> those at the smallest distance, when it is small against the word's length (1 edit for words of up
   !> to 5 characters, 2 up to 11, 3 beyond) and at most max_suggestions of them; '' when none is near.
   !> `word` itself is never suggested.
   function nearest_words(word, words) result(nearest)
      character(len=*), intent(in) :: word, words
      character(len=:), allocatable :: nearest, candidate
      integer :: start, comma, best, distance, found, limit
      nearest = ''
      limit = 1
      if (len_trim(word) > 5) limit = 2
      if (len_trim(word) > 11) limit = 3
      best = limit + 1
      found = 0
      start = 1
      do while (start <= len(words))
         comma = index(words(start:), ',')
         if (comma == 0) comma = len(words) - start + 2
         candidate = trim(adjustl(words(start:start + comma - 2)))
         start = start + comma
         if (len(candidate) == 0 .or. candidate == trim(word)) cycle
         distance = edit_distance(trim(word), candidate)
         if (distance < best) then
            best = distance
            nearest = candidate
            found = 1
         else if (distance == best .and. found < max_suggestions) then
            nearest = nearest//', '//candidate
            found = found + 1
         end if
      end do
   end function nearest_words

   !> "; did you mean &discretisation?" for `word` among `words` (comma separated), each suggestion
   !> written as `before`//word//`after` ("&", "'"...), several as "a, b or c"; '' when none is near.
   function did_you_mean(word, words, before, after) result(text)
      character(len=*), intent(in) :: word, words
      character(len=*), intent(in), optional :: before, after
      character(len=:), allocatable :: text, rest, left, right
      integer :: comma
      left = ''
      right = ''
      if (present(before)) left = before
      if (present(after)) right = after
      rest = nearest_words(word, words)
      text = ''
      if (len(rest) == 0) return
      do
         comma = index(rest, ',')
         if (comma == 0) exit
         if (len(text) > 0) text = text//', '
         text = text//left//trim(adjustl(rest(1:comma - 1)))//right
         rest = rest(comma + 1:)
      end do
      if (len(text) > 0) text = text//' or '
      text = '; did you mean '//text//left//trim(adjustl(rest))//right//'?'
   end function did_you_mean

   !> `text` with every control character (codes 0-31 and 127) written as \0, \t, \x1b..., so that a
   !> message quoting input shows what is there (a NUL byte would end the line a terminal shows).
   pure function printable(text) result(shown)
      character(len=*), intent(in) :: text
      character(len=:), allocatable :: shown
      character(len=*), parameter :: hex = '0123456789abcdef'
      integer :: i, code
      shown = ''
      do i = 1, len(text)
         code = iachar(text(i:i))
         if (code == 0) then
            shown = shown//'\0'
         else if (code == 9) then
            shown = shown//'\t'
         else if (code < 32 .or. code == 127) then
            shown = shown//'\x'//hex(code/16 + 1:code/16 + 1)//hex(mod(code, 16) + 1:mod(code, 16) + 1)
         else
            shown = shown//text(i:i)
         end if
      end do
   end function printable
end module mpm_suggest
