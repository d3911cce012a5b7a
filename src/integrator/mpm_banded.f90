!> A square banded matrix in band storage and its LU factorisation with partial pivoting: the tangent
!> of the implicit integrators, whose bandwidth is the shape's support less one (two nodes couple when
!> one particle touches both; the ghost penalty's stencil adds one). The storage is LAPACK's band format
!> (Anderson et al., LAPACK Users' Guide, 3rd ed., SIAM 1999, sec. 5.3.3, doi:10.1137/1.9780898719604):
!> A(i, j) sits in ab(2 b + 1 + i - j, j) for the bandwidth b, and the first b rows are the room the
!> factorisation needs for the fill-in of its row interchanges (U then has 2 b super-diagonals). The
!> factorisation is Gaussian elimination with partial pivoting column by column (Golub and Van Loan,
!> Matrix Computations, 4th ed., 2013, alg. 4.3.1 with sec. 3.4); the reciprocal condition number is
!> Hager's 1-norm estimate of ||A^-1||_1 as refined by Higham (W. W. Hager, SIAM J. Sci. Stat. Comput.
!> 5 (1984) 311-316; N. J. Higham, ACM TOMS 14 (1988) 381-396, alg. 4.1). The code is our own: the
!> matrices are small (one row per node) and narrow (b <= 4), and linking a BLAS for them cost every
!> run of mpm1d (OpenBLAS starts a thread pool when it is loaded). Rows and columns are numbered 1..n
!> here (the grid's nodes 0..elements are row node + 1).
module mpm_banded
   use mpm_kinds, only: dp
   implicit none
   private
   public :: banded_t, banded_init, banded_zero, banded_add, banded_multiply, banded_factor, banded_solve, &
             banded_rcond, banded_row, banded_pivot_ratio, banded_solve_negated

   !> The matrix and, after banded_factor, its LU factors and pivots.
   type :: banded_t
      integer :: n = 0
      integer :: bandwidth = 0
      real(dp), allocatable :: ab(:, :)    !< (3 bandwidth + 1, n): band storage, then the LU factors
      integer, allocatable :: pivots(:)    !< row j was interchanged with row pivots(j) at step j
      logical :: interchanged = .false.    !< some row was (pivots(j) /= j for some j)
      !> the smallest and largest |U_jj| where the factorisation formed them in passing (no interchange, every
      !> pivot finite and nonzero), else -1
      real(dp) :: smallest_pivot = -1.0_dp, largest_pivot = -1.0_dp
      real(dp) :: norm1 = 0.0_dp           !< the 1-norm of the matrix before it was factored
      logical :: factored = .false.
   end type banded_t

contains

   !> An n x n matrix of `bandwidth` sub- and super-diagonals, zero (storage kept when it fits).
   subroutine banded_init(a, n, bandwidth, cleared)
      type(banded_t), intent(inout) :: a
      integer, intent(in) :: n, bandwidth
      !> .false.: the values are left as they are (a caller that sets every one before reading any);
      !> default .true. (all zero)
      logical, intent(in), optional :: cleared
      if (allocated(a%ab)) then
         if (size(a%ab, 1) /= 3*bandwidth + 1 .or. size(a%ab, 2) /= n) deallocate (a%ab, a%pivots)
      end if
      if (.not. allocated(a%ab)) allocate (a%ab(3*bandwidth + 1, n), a%pivots(n))
      a%n = n
      a%bandwidth = bandwidth
      a%factored = .false.
      if (present(cleared)) then
         if (.not. cleared) return
      end if
      call banded_zero(a)
   end subroutine banded_init

   subroutine banded_zero(a)
      type(banded_t), intent(inout) :: a
      call zero(a%ab, size(a%ab))
      a%factored = .false.
   contains
      !> The band's storage as one run of values (gfortran cleared the rank-2 component column by column:
      !> a call of memset per column of 4 to 13 values).
      pure subroutine zero(values, count)
         integer, intent(in) :: count
         real(dp), intent(out) :: values(count)
         values = 0.0_dp
      end subroutine zero
   end subroutine banded_zero

   !> A(i, j) += value (1 <= i, j <= n, |i - j| <= bandwidth).
   pure subroutine banded_add(a, i, j, value)
      type(banded_t), intent(inout) :: a
      integer, intent(in) :: i, j
      real(dp), intent(in) :: value
      a%ab(2*a%bandwidth + 1 + i - j, j) = a%ab(2*a%bandwidth + 1 + i - j, j) + value
   end subroutine banded_add

   !> Row i of the (unfactored) matrix at columns j0..j1 (zero outside the band).
   pure function banded_row(a, i, j0, j1) result(row)
      type(banded_t), intent(in) :: a
      integer, intent(in) :: i, j0, j1
      real(dp) :: row(j0:j1)
      integer :: j
      do j = j0, j1
         if (abs(i - j) <= a%bandwidth .and. j >= 1 .and. j <= a%n) then
            row(j) = a%ab(2*a%bandwidth + 1 + i - j, j)
         else
            row(j) = 0.0_dp
         end if
      end do
   end function banded_row

   !> y = A x of the unfactored matrix.
   pure function banded_multiply(a, x) result(y)
      type(banded_t), intent(in) :: a
      real(dp), intent(in) :: x(:)
      real(dp) :: y(size(x))
      integer :: i, j, b
      b = a%bandwidth
      if (b == 1 .and. a%n >= 2) then ! (the loop below written out, its sums in the same order)
         associate (n => a%n, ab => a%ab)
            y(1) = ab(3, 1)*x(1) + ab(2, 2)*x(2)
            do i = 2, n - 1
               y(i) = ab(4, i - 1)*x(i - 1) + ab(3, i)*x(i) + ab(2, i + 1)*x(i + 1)
            end do
            y(n) = ab(4, n - 1)*x(n - 1) + ab(3, n)*x(n)
         end associate
         return
      end if
      y = 0.0_dp
      do j = 1, a%n
         do i = max(1, j - b), min(a%n, j + b)
            y(i) = y(i) + a%ab(2*b + 1 + i - j, j)*x(j)
         end do
      end do
   end function banded_multiply

   !> LU factorisation with partial pivoting in place, P A = L U: U (2 b super-diagonals) in rows 1..2b+1,
   !> the multipliers of L in rows 2b+2..3b+1. info > 0: U(info, info) is exactly zero (singular; the
   !> columns after it are still eliminated, as far as they can be).
   pure subroutine banded_factor(a, info)
      type(banded_t), intent(inout) :: a
      integer, intent(out) :: info
      integer :: i, j, c, b, d, below, pivot, last
      real(dp) :: largest, t
      b = a%bandwidth
      d = 2*b + 1 ! the row of the diagonal
      info = 0
      a%norm1 = 0.0_dp
      a%interchanged = .true.
      a%smallest_pivot = -1.0_dp
      a%largest_pivot = -1.0_dp
      if (b == 1) then
         do j = 1, a%n
            a%norm1 = max(a%norm1, abs(a%ab(2, j)) + abs(a%ab(3, j)) + abs(a%ab(4, j)))
            a%ab(1, j) = 0.0_dp ! the fill-in row
         end do
         call factor_tridiagonal(a, info)
         a%factored = info == 0
         return
      end if
      do j = 1, a%n
         a%norm1 = max(a%norm1, sum(abs(a%ab(b + 1:3*b + 1, j))))
      end do
      a%ab(1:b, :) = 0.0_dp ! the fill-in rows
      last = 0 ! the last column the eliminations so far reach
      do j = 1, a%n
         below = min(b, a%n - j)
         ! the pivot: the largest magnitude in column j on or below the diagonal (the first of equals)
         pivot = 0
         largest = abs(a%ab(d, j))
         do i = 1, below
            if (abs(a%ab(d + i, j)) > largest) then
               pivot = i
               largest = abs(a%ab(d + i, j))
            end if
         end do
         a%pivots(j) = j + pivot
         last = max(last, min(j + b + pivot, a%n))
         if (largest == 0.0_dp) then
            if (info == 0) info = j
            cycle
         end if
         if (pivot /= 0) then ! rows j and j + pivot, columns j..last: A(r, c) at ab(d + r - c, c)
            do c = j, last
               t = a%ab(d + j - c, c)
               a%ab(d + j - c, c) = a%ab(d + j + pivot - c, c)
               a%ab(d + j + pivot - c, c) = t
            end do
         end if
         a%ab(d + 1:d + below, j) = a%ab(d + 1:d + below, j)/a%ab(d, j)
         do c = j + 1, last
            t = a%ab(d + j - c, c)
            if (t /= 0.0_dp) a%ab(d + j + 1 - c:d + j + below - c, c) = a%ab(d + j + 1 - c:d + j + below - c, c) - &
                                                                        a%ab(d + 1:d + below, j)*t
         end do
      end do
      a%factored = info == 0
   end subroutine banded_factor

   !> banded_factor for bandwidth 1 (the hat without the ghost penalty: the common case), the same
   !> operations in the same order written out for the three rows of a column (the general loop's
   !> bookkeeping cost it four times the arithmetic): bit for bit the general code's factors.
   pure subroutine factor_tridiagonal(a, info)
      type(banded_t), intent(inout) :: a
      integer, intent(inout) :: info
      call factor_rows(a%n, a%ab, a%pivots, info, a%interchanged, a%smallest_pivot, a%largest_pivot)
   end subroutine factor_tridiagonal

   !> factor_tridiagonal on the band as an explicit-shape array (gfortran indexed the component through its
   !> descriptor, reloaded after every store: twice the instructions).
   pure subroutine factor_rows(n, ab, pivots, info, interchanged, smallest, largest)
      integer, intent(in) :: n
      real(dp), intent(inout) :: ab(4, n)
      integer, intent(out) :: pivots(n)
      integer, intent(inout) :: info
      logical, intent(out) :: interchanged
      !> min and max |U_jj| where every column took the first loop and the last pivot is a number, else -1
      real(dp), intent(out) :: smallest, largest
      integer :: j, first
      real(dp) :: l, t, pivot, upper
      ! column j: U(j-2, j) in ab(1, j) (fill-in), U(j-1, j) in ab(2, j), the diagonal in ab(3, j), the
      ! sub-diagonal (then the multiplier) in ab(4, j)
      interchanged = .false.
      ! the columns before the first that needs an interchange or has a zero pivot (all of them, where
      ! the diagonal dominates, as the inertia makes it): the loop below's operations with the pivot carried
      ! in a register (that loop reloads it through memory after each store: twice the time); the fill-in
      ! row stays zero, so its updates are none
      first = n
      smallest = huge(1.0_dp)
      largest = 0.0_dp
      if (n >= 1) pivot = ab(3, 1)
      do j = 1, n - 1
         if (.not. abs(ab(4, j)) <= abs(pivot) .or. pivot == 0.0_dp) then
            first = j
            exit
         end if
         if (abs(pivot) < smallest) smallest = abs(pivot)
         if (abs(pivot) > largest) largest = abs(pivot)
         pivots(j) = j
         l = ab(4, j)/pivot
         ab(4, j) = l
         upper = ab(2, j + 1)
         pivot = ab(3, j + 1)
         if (upper /= 0.0_dp) pivot = pivot - l*upper
         ab(3, j + 1) = pivot
      end do
      if (first == n .and. n >= 2 .and. abs(pivot) <= huge(1.0_dp)) then
         smallest = min(smallest, abs(pivot))
         largest = max(largest, abs(pivot))
      else
         smallest = -1.0_dp
         largest = -1.0_dp
      end if
      do j = first, n - 1
         pivots(j) = j
         if (abs(ab(4, j)) > abs(ab(3, j))) then ! rows j and j + 1, columns j .. j + 2
            pivots(j) = j + 1
            interchanged = .true.
            t = ab(3, j); ab(3, j) = ab(4, j); ab(4, j) = t
            t = ab(2, j + 1); ab(2, j + 1) = ab(3, j + 1); ab(3, j + 1) = t
            if (j + 2 <= n) then
               t = ab(1, j + 2); ab(1, j + 2) = ab(2, j + 2); ab(2, j + 2) = t
            end if
         end if
         if (ab(3, j) == 0.0_dp) then
            if (info == 0) info = j
            cycle
         end if
         l = ab(4, j)/ab(3, j)
         ab(4, j) = l
         if (ab(2, j + 1) /= 0.0_dp) ab(3, j + 1) = ab(3, j + 1) - l*ab(2, j + 1)
         if (j + 2 <= n) then
            if (ab(1, j + 2) /= 0.0_dp) ab(2, j + 2) = ab(2, j + 2) - l*ab(1, j + 2)
         end if
      end do
      pivots(n) = n
      if (ab(3, n) == 0.0_dp .and. info == 0) info = n
   end subroutine factor_rows

   !> Solve A X = B in place with the factors of banded_factor, every column of b.
   pure subroutine banded_solve(a, b, info)
      type(banded_t), intent(in) :: a
      real(dp), intent(inout), contiguous :: b(:, :)
      integer, intent(out) :: info
      integer :: k
      info = 0
      if (size(b, 1) /= a%n) then
         info = -1
         return
      end if
      do k = 1, size(b, 2)
         call solve_one(a, b(:, k), .false.)
      end do
   end subroutine banded_solve

   !> x := A^-1 b with b = -r on the rows where `mask` holds and 0 on the others (Newton's step from a
   !> residual), from the factors: banded_solve's operations; with bandwidth 1 and no interchange, b is formed
   !> in the first sweep (solve_rows'), not in a pass of its own.
   pure subroutine banded_solve_negated(a, r, mask, x)
      type(banded_t), intent(in) :: a
      real(dp), intent(in) :: r(:)
      logical, intent(in) :: mask(:)
      real(dp), intent(out) :: x(:)
      if (a%bandwidth == 1 .and. .not. a%interchanged .and. a%n >= 1) then
         call solve_rows_negated(a%n, a%ab, r, mask, x)
      else
         x = merge(-r, 0.0_dp, mask)
         call solve_one(a, x, .false.)
      end if
   end subroutine banded_solve_negated

   !> solve_rows without an interchange for b = merge(-r, 0, mask) (banded_solve_negated).
   pure subroutine solve_rows_negated(n, ab, r, mask, x)
      integer, intent(in) :: n
      real(dp), intent(in) :: ab(4, n), r(n)
      logical, intent(in) :: mask(n)
      real(dp), intent(out) :: x(n)
      real(dp) :: y
      integer :: j
      y = merge(-r(1), 0.0_dp, mask(1))
      x(1) = y
      do j = 1, n - 1
         y = merge(-r(j + 1), 0.0_dp, mask(j + 1)) - ab(4, j)*y
         x(j + 1) = y
      end do
      call back_substitute(n, ab, x)
   end subroutine solve_rows_negated

   !> U x = y of a bandwidth-1 factorisation without an interchange (no fill-in), y in x: the last value
   !> carried in a register along the chain of divisions (solve_rows, solve_rows_negated).
   pure subroutine back_substitute(n, ab, x)
      integer, intent(in) :: n
      real(dp), intent(in) :: ab(4, n)
      real(dp), intent(inout) :: x(n)
      real(dp) :: y
      integer :: j
      y = x(n)/ab(3, n)
      x(n) = y
      do j = n - 1, 1, -1
         y = (x(j) - ab(2, j + 1)*y)/ab(3, j)
         x(j) = y
      end do
   end subroutine back_substitute

   !> x := A^-1 x, or (transposed) A^-T x, from the factors P A = L U.
   pure subroutine solve_one(a, x, transposed)
      type(banded_t), intent(in) :: a
      real(dp), intent(inout) :: x(:)
      logical, intent(in) :: transposed
      integer :: j, b, d, below, above
      b = a%bandwidth
      d = 2*b + 1
      if (b == 1 .and. .not. transposed) then ! (the loops below written out: the same operations)
         call solve_rows(a%n, a%ab, a%pivots, a%interchanged, x)
      else if (.not. transposed) then
         do j = 1, a%n - 1 ! L y = P x
            below = min(b, a%n - j)
            call interchange(x, j, a%pivots(j))
            x(j + 1:j + below) = x(j + 1:j + below) - a%ab(d + 1:d + below, j)*x(j)
         end do
         do j = a%n, 1, -1 ! U x = y
            above = min(j - 1, 2*b)
            x(j) = x(j)/a%ab(d, j)
            x(j - above:j - 1) = x(j - above:j - 1) - a%ab(d - above:d - 1, j)*x(j)
         end do
      else
         do j = 1, a%n ! U^T y = x
            above = min(j - 1, 2*b)
            x(j) = (x(j) - sum(a%ab(d - above:d - 1, j)*x(j - above:j - 1)))/a%ab(d, j)
         end do
         do j = a%n - 1, 1, -1 ! L^T P x = y
            below = min(b, a%n - j)
            x(j) = x(j) - sum(a%ab(d + 1:d + below, j)*x(j + 1:j + below))
            call interchange(x, j, a%pivots(j))
         end do
      end if
   end subroutine solve_one

   !> solve_one for bandwidth 1 (not transposed) on explicit-shape arrays (as factor_rows).
   pure subroutine solve_rows(n, ab, pivots, interchanged, x)
      integer, intent(in) :: n
      real(dp), intent(in) :: ab(4, n)
      integer, intent(in) :: pivots(n)
      logical, intent(in) :: interchanged
      real(dp), intent(inout) :: x(n)
      real(dp) :: t, y
      integer :: j
      if (.not. interchanged .and. n >= 1) then
         ! no interchange (so no fill-in: ab(1, :) = 0): the loops below' operations with the last value
         ! carried in a register
         y = x(1)
         do j = 1, n - 1
            y = x(j + 1) - ab(4, j)*y
            x(j + 1) = y
         end do
         call back_substitute(n, ab, x)
         return
      end if
      do j = 1, n - 1
         if (pivots(j) /= j) then
            t = x(pivots(j))
            x(pivots(j)) = x(j)
            x(j) = t
         end if
         x(j + 1) = x(j + 1) - ab(4, j)*x(j)
      end do
      do j = n, 1, -1
         x(j) = x(j)/ab(3, j)
         if (j >= 3) x(j - 2) = x(j - 2) - ab(1, j)*x(j)
         if (j >= 2) x(j - 1) = x(j - 1) - ab(2, j)*x(j)
      end do
   end subroutine solve_rows

   !> x(i) and x(l) exchanged (nothing when l = i).
   pure subroutine interchange(x, i, l)
      real(dp), intent(inout) :: x(:)
      integer, intent(in) :: i, l
      real(dp) :: t
      if (l == i) return
      t = x(l)
      x(l) = x(i)
      x(i) = t
   end subroutine interchange

   !> The smallest diagonal entry of the LU factors' U relative to the largest, min |U_jj|/max |U_ii|: free
   !> after banded_factor, and the row of a nearly empty node is where it shrinks.
   real(dp) function banded_pivot_ratio(a) result(ratio)
      type(banded_t), intent(in) :: a
      real(dp) :: largest
      if (a%smallest_pivot >= 0.0_dp) then ! (formed by the factorisation)
         ratio = a%smallest_pivot
         if (a%largest_pivot > 0.0_dp) ratio = ratio/a%largest_pivot
         return
      end if
      largest = maxval(abs(a%ab(2*a%bandwidth + 1, :)))
      ratio = minval(abs(a%ab(2*a%bandwidth + 1, :)))
      if (largest > 0.0_dp) ratio = ratio/largest
   end function banded_pivot_ratio

   !> An estimate of 1/(||A||_1 ||A^-1||_1) from the factors: near 1 well conditioned, near eps numerically
   !> singular; 0 when the matrix is singular. ||A^-1||_1 by Hager's method (the largest |A^-1 x|_1 over the
   !> vertices x = e_j of the unit 1-ball, found by a gradient ascent of at most five steps, each one solve
   !> with A and one with A^T) and Higham's extra test vector x_i = (-1)^(i+1) (1 + (i-1)/(n-1)), which
   !> catches the matrices where the ascent stops early. The estimate never exceeds ||A^-1||_1, so the
   !> reciprocal condition number is never underestimated; it is exact or within a factor 3 in practice.
   real(dp) function banded_rcond(a) result(rcond)
      type(banded_t), intent(in) :: a
      real(dp), allocatable :: x(:), sign_x(:), z(:)
      real(dp) :: estimate, previous
      integer :: n, i, j, last, iteration
      n = a%n
      rcond = 0.0_dp
      if (.not. a%factored .or. a%norm1 == 0.0_dp) return
      if (n == 1) then
         rcond = abs(a%ab(2*a%bandwidth + 1, 1))/a%norm1
         return
      end if
      allocate (x(n), sign_x(n), z(n))
      x = 1.0_dp/n
      call solve_one(a, x, .false.)
      estimate = sum(abs(x))
      sign_x = sign(1.0_dp, x)
      z = sign_x
      call solve_one(a, z, .true.)
      j = maxloc(abs(z), 1)
      do iteration = 2, 5
         x = 0.0_dp
         x(j) = 1.0_dp
         call solve_one(a, x, .false.)
         previous = estimate
         estimate = sum(abs(x))
         if (all(sign(1.0_dp, x) == sign_x) .or. estimate <= previous) then
            estimate = max(estimate, previous)
            exit
         end if
         sign_x = sign(1.0_dp, x)
         z = sign_x
         call solve_one(a, z, .true.)
         last = j
         j = maxloc(abs(z), 1)
         if (abs(z(last)) == abs(z(j))) exit
      end do
      do i = 1, n
         x(i) = merge(1.0_dp, -1.0_dp, mod(i, 2) == 1)*(1.0_dp + real(i - 1, dp)/real(n - 1, dp))
      end do
      call solve_one(a, x, .false.)
      estimate = max(estimate, 2.0_dp*sum(abs(x))/(3.0_dp*n))
      rcond = (1.0_dp/estimate)/a%norm1
   end function banded_rcond
end module mpm_banded
