!> A square banded matrix in LAPACK's band storage and its LU factorisation with partial pivoting by
!> LAPACK (dgbtrf, dgbtrs; the reciprocal condition number by dgbcon): the tangent of the implicit
!> integrators, whose bandwidth is the shape's support less one (two nodes couple when one particle
!> touches both; the ghost penalty's stencil adds one). LAPACK's band storage (Anderson et al., LAPACK
!> Users' Guide, 3rd ed., SIAM 1999, sec. 5.3.3, doi:10.1137/1.9780898719604): A(i, j) sits in
!> ab(kl + ku + 1 + i - j, j) with kl = ku = bandwidth, and the first kl rows are the room dgbtrf needs
!> for the fill-in of the row interchanges. Rows and columns are numbered 1..n here (the grid's nodes
!> 0..elements are row node + 1). A tridiagonal matrix (bandwidth 1: linear shapes without the ghost
!> penalty) is factored by LAPACK's tridiagonal routines instead (dgttrf, dgttrs, dgtcon: the same LU with
!> partial pivoting, without the general band code's BLAS call per column).
module mpm_banded
   use mpm_kinds, only: dp
   implicit none
   private
   public :: banded_t, banded_init, banded_zero, banded_add, banded_multiply, banded_factor, banded_solve, &
             banded_rcond, banded_row, banded_pivot_ratio

   !> The matrix and, after banded_factor, its LU factors and pivots.
   type :: banded_t
      integer :: n = 0
      integer :: bandwidth = 0
      real(dp), allocatable :: ab(:, :)    !< (3 bandwidth + 1, n): band storage (dgbtrf's layout)
      integer, allocatable :: pivots(:)
      real(dp) :: norm1 = 0.0_dp           !< the 1-norm of the matrix before it was factored (for dgbcon)
      logical :: factored = .false.
      !> bandwidth 1: the sub-, main and super-diagonal and dgttrf's second super-diagonal of U
      real(dp), allocatable :: lower(:), main(:), upper(:), upper2(:)
   end type banded_t

   interface
      subroutine dgbtrf(m, n, kl, ku, ab, ldab, ipiv, info)
         import :: dp
         integer, intent(in) :: m, n, kl, ku, ldab
         real(dp), intent(inout) :: ab(ldab, *)
         integer, intent(out) :: ipiv(*), info
      end subroutine dgbtrf
      subroutine dgbtrs(trans, n, kl, ku, nrhs, ab, ldab, ipiv, b, ldb, info)
         import :: dp
         character, intent(in) :: trans
         integer, intent(in) :: n, kl, ku, nrhs, ldab, ldb
         real(dp), intent(in) :: ab(ldab, *)
         integer, intent(in) :: ipiv(*)
         real(dp), intent(inout) :: b(ldb, *)
         integer, intent(out) :: info
      end subroutine dgbtrs
      subroutine dgbcon(norm, n, kl, ku, ab, ldab, ipiv, anorm, rcond, work, iwork, info)
         import :: dp
         character, intent(in) :: norm
         integer, intent(in) :: n, kl, ku, ldab
         real(dp), intent(in) :: ab(ldab, *), anorm
         integer, intent(in) :: ipiv(*)
         real(dp), intent(out) :: rcond, work(*)
         integer, intent(out) :: iwork(*), info
      end subroutine dgbcon
      subroutine dgttrf(n, dl, d, du, du2, ipiv, info)
         import :: dp
         integer, intent(in) :: n
         real(dp), intent(inout) :: dl(*), d(*), du(*)
         real(dp), intent(out) :: du2(*)
         integer, intent(out) :: ipiv(*), info
      end subroutine dgttrf
      subroutine dgttrs(trans, n, nrhs, dl, d, du, du2, ipiv, b, ldb, info)
         import :: dp
         character, intent(in) :: trans
         integer, intent(in) :: n, nrhs, ldb
         real(dp), intent(in) :: dl(*), d(*), du(*), du2(*)
         integer, intent(in) :: ipiv(*)
         real(dp), intent(inout) :: b(ldb, *)
         integer, intent(out) :: info
      end subroutine dgttrs
      subroutine dgtcon(norm, n, dl, d, du, du2, ipiv, anorm, rcond, work, iwork, info)
         import :: dp
         character, intent(in) :: norm
         integer, intent(in) :: n
         real(dp), intent(in) :: dl(*), d(*), du(*), du2(*), anorm
         integer, intent(in) :: ipiv(*)
         real(dp), intent(out) :: rcond, work(*)
         integer, intent(out) :: iwork(*), info
      end subroutine dgtcon
   end interface

contains

   !> An n x n matrix of `bandwidth` sub- and super-diagonals, zero (storage kept when it fits).
   subroutine banded_init(a, n, bandwidth)
      type(banded_t), intent(inout) :: a
      integer, intent(in) :: n, bandwidth
      if (allocated(a%ab)) then
         if (size(a%ab, 1) /= 3*bandwidth + 1 .or. size(a%ab, 2) /= n) deallocate (a%ab, a%pivots)
      end if
      if (.not. allocated(a%ab)) allocate (a%ab(3*bandwidth + 1, n), a%pivots(n))
      a%n = n
      a%bandwidth = bandwidth
      call banded_zero(a)
   end subroutine banded_init

   subroutine banded_zero(a)
      type(banded_t), intent(inout) :: a
      a%ab = 0.0_dp
      a%factored = .false.
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
      y = 0.0_dp
      do j = 1, a%n
         do i = max(1, j - b), min(a%n, j + b)
            y(i) = y(i) + a%ab(2*b + 1 + i - j, j)*x(j)
         end do
      end do
   end function banded_multiply

   !> LU factorisation (dgbtrf in place; tridiagonal: dgttrf on copies of the diagonals); info > 0:
   !> U(info, info) is exactly zero (singular).
   subroutine banded_factor(a, info)
      type(banded_t), intent(inout) :: a
      integer, intent(out) :: info
      integer :: j, b
      b = a%bandwidth
      a%norm1 = 0.0_dp
      do j = 1, a%n
         a%norm1 = max(a%norm1, sum(abs(a%ab(b + 1:3*b + 1, j))))
      end do
      if (b == 1) then ! tridiagonal: A(j+1, j) at ab(4, j), A(j, j) at ab(3, j), A(j, j+1) at ab(2, j+1)
         if (allocated(a%main)) then
            if (size(a%main) /= a%n) deallocate (a%lower, a%main, a%upper, a%upper2)
         end if
         if (.not. allocated(a%main)) allocate (a%lower(a%n), a%main(a%n), a%upper(a%n), a%upper2(a%n))
         a%main = a%ab(3, 1:a%n)
         a%lower(1:a%n - 1) = a%ab(4, 1:a%n - 1)
         a%upper(1:a%n - 1) = a%ab(2, 2:a%n)
         call dgttrf(a%n, a%lower, a%main, a%upper, a%upper2, a%pivots, info)
      else
         call dgbtrf(a%n, a%n, b, b, a%ab, 3*b + 1, a%pivots, info)
      end if
      a%factored = info == 0
   end subroutine banded_factor

   !> Solve A X = B in place with the factors of banded_factor (dgbtrs), every column of b.
   subroutine banded_solve(a, b, info)
      type(banded_t), intent(in) :: a
      real(dp), intent(inout), contiguous :: b(:, :)
      integer, intent(out) :: info
      if (a%bandwidth == 1) then
         call dgttrs('N', a%n, size(b, 2), a%lower, a%main, a%upper, a%upper2, a%pivots, b, size(b, 1), info)
      else
         call dgbtrs('N', a%n, a%bandwidth, a%bandwidth, size(b, 2), a%ab, 3*a%bandwidth + 1, a%pivots, b, &
                     size(b, 1), info)
      end if
   end subroutine banded_solve

   !> The smallest diagonal entry of the LU factors' U relative to the largest, min |U_jj|/max |U_ii|: free
   !> after banded_factor, and the row of a nearly empty node is where it shrinks.
   real(dp) function banded_pivot_ratio(a) result(ratio)
      type(banded_t), intent(in) :: a
      real(dp) :: largest
      if (a%bandwidth == 1) then
         largest = maxval(abs(a%main))
         ratio = minval(abs(a%main))
      else
         largest = maxval(abs(a%ab(2*a%bandwidth + 1, :)))
         ratio = minval(abs(a%ab(2*a%bandwidth + 1, :)))
      end if
      if (largest > 0.0_dp) ratio = ratio/largest
   end function banded_pivot_ratio

   !> LAPACK's estimate of 1/(||A||_1 ||A^-1||_1) from the factors (dgbcon): near 1 well conditioned,
   !> near eps numerically singular.
   real(dp) function banded_rcond(a) result(rcond)
      type(banded_t), intent(in) :: a
      real(dp), allocatable :: work(:)
      integer, allocatable :: iwork(:)
      integer :: info
      allocate (work(3*a%n), iwork(a%n))
      if (a%bandwidth == 1) then
         call dgtcon('1', a%n, a%lower, a%main, a%upper, a%upper2, a%pivots, a%norm1, rcond, work, iwork, info)
      else
         call dgbcon('1', a%n, a%bandwidth, a%bandwidth, a%ab, 3*a%bandwidth + 1, a%pivots, a%norm1, rcond, work, &
                     iwork, info)
      end if
      if (info /= 0) rcond = 0.0_dp
   end function banded_rcond
end module mpm_banded
