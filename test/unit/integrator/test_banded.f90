!> The banded LU of the implicit integrators (mpm_banded) against independent expectations:
!> - the 1-D Laplacian tridiag(-1, 2, -1) of order n, whose inverse is known in closed form,
!>   (A^-1)_ij = min(i, j) (n + 1 - max(i, j))/(n + 1): the solve against it, and the condition estimate
!>   against 1/(||A||_1 ||A^-1||_1) with ||A||_1 = 4 (Hager's estimate is exact on this matrix);
!> - random band matrices (bandwidths 1-3, sizes 1-40) with diagonals 1e-6 of the off-diagonals, so that rows must be
!>   interchanged: the solution against a dense Gaussian elimination with partial pivoting written out
!>   here, and the residual |A x - r| at round-off; the condition estimate against the exact reciprocal
!>   condition number from the dense inverse: never below it, and within a factor 10 of it; the
!>   product A x against the dense one;
!> - a matrix with an exactly zero column gives info = that column and rcond 0;
!> - Newton's step from a residual, banded_solve_negated, against banded_solve of -r on the masked rows
!>   (0 on the others): bit for bit, with and without row interchanges, bandwidths 1 and 2.
program test_banded
   use mpm_kinds, only: dp
   use mpm_strings, only: str
   use mpm_banded, only: banded_t, banded_init, banded_add, banded_factor, banded_solve, banded_rcond, &
                         banded_multiply, banded_pivot_ratio, banded_solve_negated
   use mpm_testing, only: tester_t, tester
   implicit none
   type(tester_t) :: t
   integer :: seed = 12345

   t = tester('test_banded')
   if (t%case('laplacian')) then
      call laplacian(7)
      call laplacian(40)
   end if
   if (t%case('random_matrices')) call random_matrices()
   if (t%case('singular')) call singular()
   if (t%case('negated_solve')) call negated_solve()
   call t%finish()

contains

   !> A deterministic uniform number in [-1, 1) (Park-Miller), independent of the compiler's generator.
   real(dp) function uniform()
      seed = int(mod(16807_8*seed, 2147483647_8))
      uniform = 2.0_dp*real(seed, dp)/2147483647.0_dp - 1.0_dp
   end function uniform

   subroutine laplacian(n)
      integer, intent(in) :: n
      type(banded_t) :: a
      real(dp) :: rhs(n, 1), exact(n), inverse_norm
      integer :: i, j, info
      call banded_init(a, n, 1)
      do i = 1, n
         call banded_add(a, i, i, 2.0_dp)
         if (i > 1) call banded_add(a, i, i - 1, -1.0_dp)
         if (i < n) call banded_add(a, i, i + 1, -1.0_dp)
      end do
      ! the right-hand side of the exact solution x_i = i^2 (interior rows: -1 + 4i - ... = -2)
      do i = 1, n
         exact(i) = real(i, dp)**2
      end do
      rhs(:, 1) = banded_multiply(a, exact)
      call banded_factor(a, info)
      call t%check('laplacian n='//str(n)//': factored', info == 0 .and. a%factored, 'info '//str(info))
      call banded_solve(a, rhs, info)
      call t%check_close('laplacian n='//str(n)//': solve gives x_i = i^2', maxval(abs(rhs(:, 1) - exact)), 0.0_dp, &
                         atol=1.0e-12_dp*maxval(exact))
      inverse_norm = 0.0_dp
      do j = 1, n
         inverse_norm = max(inverse_norm, sum([(real(min(i, j)*(n + 1 - max(i, j)), dp)/(n + 1), i = 1, n)]))
      end do
      call t%check_close('laplacian n='//str(n)//': rcond = 1/(4 ||A^-1||_1)', banded_rcond(a), &
                         1.0_dp/(4.0_dp*inverse_norm), rtol=1.0e-12_dp)
      call t%check('laplacian n='//str(n)//': no interchange (diagonally dominant)', &
                   all(a%pivots == [(i, i = 1, n)]))
      call t%check_close('laplacian n='//str(n)//': pivot ratio (n+1)/n / 2', banded_pivot_ratio(a), &
                         (real(n + 1, dp)/n)/2.0_dp, rtol=1.0e-14_dp)
   end subroutine laplacian

   subroutine random_matrices()
      integer, parameter :: sizes(5) = [1, 2, 5, 13, 40]
      integer :: b, m, n, i, j, info, swaps, worst_case
      type(banded_t) :: a
      real(dp), allocatable :: dense(:, :), x(:), rhs(:, :), reference(:), inverse(:, :)
      real(dp) :: worst_error, worst_residual, exact, ratio, lowest, highest, worst_product
      swaps = 0
      worst_product = 0.0_dp
      worst_error = 0.0_dp
      worst_residual = 0.0_dp
      lowest = huge(1.0_dp)
      highest = 0.0_dp
      worst_case = 0
      do b = 1, 3
         do m = 1, size(sizes)
            n = sizes(m)
            call banded_init(a, n, b)
            allocate (dense(n, n), x(n), rhs(n, 1), reference(n), inverse(n, n))
            dense = 0.0_dp
            do j = 1, n
               do i = max(1, j - b), min(n, j + b)
                  dense(i, j) = uniform()
                  if (i == j) dense(i, j) = 1.0e-6_dp*dense(i, j) ! small diagonals: rows must be interchanged
                  call banded_add(a, i, j, dense(i, j))
               end do
            end do
            do i = 1, n
               x(i) = uniform()
            end do
            rhs(:, 1) = matmul(dense, x)
            worst_product = max(worst_product, maxval(abs(banded_multiply(a, x) - rhs(:, 1))))
            reference = dense_solve(dense, rhs(:, 1))
            call banded_factor(a, info)
            call t%check('random b='//str(b)//' n='//str(n)//': factored', info == 0, 'info '//str(info))
            swaps = swaps + count(a%pivots /= [(i, i = 1, n)])
            call banded_solve(a, rhs, info)
            worst_error = max(worst_error, maxval(abs(rhs(:, 1) - reference))/maxval(abs(reference)))
            worst_residual = max(worst_residual, maxval(abs(matmul(dense, rhs(:, 1)) - matmul(dense, x)))/ &
                                 (maxval(sum(abs(dense), 2))*maxval(abs(rhs(:, 1)))))
            do j = 1, n
               x = 0.0_dp
               x(j) = 1.0_dp
               inverse(:, j) = dense_solve(dense, x)
            end do
            exact = 1.0_dp/(maxval(sum(abs(dense), 1))*maxval(sum(abs(inverse), 1)))
            ratio = banded_rcond(a)/exact
            if (ratio < lowest .or. ratio > highest) worst_case = 10*b + m
            lowest = min(lowest, ratio)
            highest = max(highest, ratio)
            deallocate (dense, x, rhs, reference, inverse)
         end do
      end do
      call t%check_close('random: banded_multiply = the dense product', worst_product, 0.0_dp, atol=1.0e-14_dp)
      call t%check('random: rows were interchanged (the pivoting is exercised)', swaps > 10, str(swaps)//' interchanges')
      call t%check_close('random: solution = dense elimination', worst_error, 0.0_dp, atol=1.0e-10_dp)
      call t%check_close('random: residual |A x - r| at round-off', worst_residual, 0.0_dp, atol=1.0e-14_dp)
      call t%check('random: rcond estimate in [exact, 10 exact]', lowest >= 1.0_dp - 1.0e-10_dp .and. highest <= 10.0_dp, &
                   'estimate/exact in ['//str(lowest)//', '//str(highest)//'], last extreme case '//str(worst_case))
   end subroutine random_matrices

   subroutine negated_solve()
      integer, parameter :: n = 23
      integer :: b, k, i, j, info
      type(banded_t) :: a
      real(dp) :: r(n), x(n), rhs(n, 1), diagonal
      logical :: mask(n)
      do k = 1, 3
         b = merge(2, 1, k == 3)
         diagonal = merge(1.0e-6_dp, 10.0_dp, k == 2) ! (k = 2: small diagonals, rows interchanged)
         call banded_init(a, n, b)
         do j = 1, n
            do i = max(1, j - b), min(n, j + b)
               call banded_add(a, i, j, merge(diagonal*(1.5_dp + uniform()), uniform(), i == j))
            end do
            r(j) = uniform()
            mask(j) = uniform() > -0.6_dp
         end do
         call banded_factor(a, info)
         ! (bandwidth 1: the interchanges the solve must follow where the diagonals are small, none where
         ! they dominate; wider bands are always solved the general way)
         if (b == 1) call t%check('b=1: rows interchanged '//merge('where the diagonals are small', &
                                                                   'nowhere else                 ', k == 2), &
                                  a%interchanged .eqv. (k == 2))
         rhs(:, 1) = merge(-r, 0.0_dp, mask)
         call banded_solve(a, rhs, info)
         call banded_solve_negated(a, r, mask, x)
         call t%check('b='//str(b)//merge(' with interchanges   ', ' without interchanges', a%interchanged)// &
                      ': the same step bit for bit', all(x == rhs(:, 1)), 'largest difference '// &
                      str(maxval(abs(x - rhs(:, 1)))))
      end do
   end subroutine negated_solve

   !> Dense Gaussian elimination with partial pivoting (row interchanges), a copy of the matrix.
   function dense_solve(matrix, r) result(x)
      real(dp), intent(in) :: matrix(:, :), r(:)
      real(dp) :: x(size(r)), work(size(r), size(r) + 1), row(size(r) + 1)
      integer :: n, i, k, p
      n = size(r)
      work(:, 1:n) = matrix
      work(:, n + 1) = r
      do k = 1, n
         p = k - 1 + maxloc(abs(work(k:n, k)), 1)
         row = work(k, :)
         work(k, :) = work(p, :)
         work(p, :) = row
         do i = k + 1, n
            work(i, k:) = work(i, k:) - work(i, k)/work(k, k)*work(k, k:)
         end do
      end do
      do i = n, 1, -1
         x(i) = (work(i, n + 1) - sum(work(i, i + 1:n)*x(i + 1:n)))/work(i, i)
      end do
   end function dense_solve

   subroutine singular()
      type(banded_t) :: a
      integer :: i, info
      call banded_init(a, 6, 2)
      do i = 1, 6
         if (i /= 4) call banded_add(a, i, i, 1.0_dp + i)
         if (i > 1 .and. i /= 5) call banded_add(a, i, i - 1, 0.5_dp)
      end do
      ! column 4 is zero: rows 4 (diagonal) and 5 (sub-diagonal) left out
      call banded_factor(a, info)
      call t%check('zero column 4: info = 4', info == 4, 'info '//str(info))
      call t%check('zero column 4: not factored, rcond 0', .not. a%factored .and. banded_rcond(a) == 0.0_dp)
   end subroutine singular
end program test_banded
