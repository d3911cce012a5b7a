!> Properties every shape function must have, checked for each shape on a grid with empty
!> margin cells: partition of unity, gradients summing to zero, linear fields reproduced exactly
!> (sum N_I x_I = x and sum dN_I x_I = 1), weights continuous as a particle crosses a node, and
!> particles outside the domain flagged, gradients the derivatives of the weights. GIMP boxes of
!> half-length dx/4 (ugimp: 2 particles per cell) and of random half-lengths up to dx/2 (cpgimp), whose
!> weights are also checked against the box averages of the hat functions by quadrature. CPDI's domains
!> (the same random half-lengths) against their closed form: the mean of the hat at the two corners, and
!> the mean of the hat's derivative over the domain by quadrature (CPDI's gradient is that mean, not the
!> derivative of its weight, which differs where a node lies inside the domain); a domain whose corners lie
!> in cells more than two apart (more than the four nodes it may touch) is flagged as stretched.
program test_shape_functions
   use, intrinsic :: ieee_arithmetic, only: ieee_value, ieee_quiet_nan, ieee_positive_inf
   use mpm_kinds, only: dp
   use mpm_errors, only: error_t
   use mpm_grid, only: grid_t, grid_init
   use mpm_shape, only: shape_cache_t, evaluate_shapes, shape_name, all_shapes, shape_ugimp, shape_cpgimp, shape_bspline2, &
                        shape_bspline3, shape_cpdi
   use mpm_testing, only: tester_t, tester
   use mpm_shape_range, only: inside_range
   implicit none
   type(tester_t) :: t
   integer :: s
   t = tester('test_shape_functions')
   do s = 1, size(all_shapes)
      if (t%case(shape_name(all_shapes(s)))) call properties(all_shapes(s))
   end do
   if (t%case('range_test')) call range_test()
   call t%finish()

contains

   subroutine properties(kind)
      integer, intent(in) :: kind
      type(grid_t) :: grid
      type(shape_cache_t) :: cache, left, right, many
      type(error_t), allocatable :: error
      real(dp), allocatable :: x(:), node_x(:), half(:)
      real(dp) :: h, d, lp
      integer :: p, k, outside, n, i
      character(len=:), allocatable :: name
      name = shape_name(kind)//': '
      call grid_init(grid, 7, 3.5_dp, 1.0_dp, error, margin=3, element_shares=.false.)
      node_x = [(grid%origin + k*grid%dx, k=0, grid%elements)]
      n = 997
      allocate (x(n), half(n))
      call random_number(x)
      ! inside the grid by the widest support (2 cells), so that no particle may be flagged
      x = grid%origin + 2*grid%dx + x*(grid%length - 4*grid%dx)
      call random_number(half)
      half = merge(0.5_dp*grid%dx*max(half, 1.0e-3_dp), 0.25_dp*grid%dx + 0*half, kind == shape_cpgimp .or. &
                                                                                   kind == shape_cpdi)
      lp = 0.25_dp*grid%dx
      cache%kind = kind
      call evaluate(cache, grid, x, outside, half)
      call t%check(name//'no particle inside the domain is flagged', outside == 0)
      do p = 1, n
         associate (w => cache%weight(p, :), g => cache%gradient(p, :), i0 => cache%first(p))
            call t%check_close(name//'partition of unity', sum(w), 1.0_dp, atol=1.0e-14_dp)
            call t%check_close(name//'gradients sum to zero', sum(g), 0.0_dp, atol=1.0e-12_dp)
            call t%check_close(name//'sum N_I x_I = x', sum(w*node_x(i0 + 1:i0 + cache%support)), x(p), rtol=1.0e-14_dp)
            call t%check_close(name//'sum dN_I x_I = 1', sum(g*node_x(i0 + 1:i0 + cache%support)), 1.0_dp, rtol=1.0e-12_dp)
            call t%check(name//'weights in [0, 1]', all(w >= 0.0_dp .and. w <= 1.0_dp))
         end associate
      end do
      ! continuity across node 4: just left and just right give the same nodal weights
      h = 1.0e-9_dp*grid%dx
      left%kind = kind
      right%kind = kind
      ! (and, for GIMP, across the points where the box edge crosses a node: x_I -+ l_p)
      do i = -1, 1
         d = i*lp
         call evaluate(left, grid, [node_x(5) + d - h], outside, [lp])
         call evaluate(right, grid, [node_x(5) + d + h], outside, [lp])
         do k = 2, 6
            call t%check_close(name//'weight of node '//achar(48 + k)//' continuous', nodal(left, k), &
                               nodal(right, k), atol=1.0e-8_dp)
         end do
      end do
      ! gradients are the derivatives of the weights (central differences, between nodes); CPDI's the mean
      ! derivative over the domain, and its weights the mean of the hat at the corners
      if (kind == shape_cpdi) call cpdi_closed_form(cache, grid, node_x, x, half)
      d = 1.0e-6_dp*grid%dx
      do p = 1, merge(0, 50, kind == shape_cpdi)
         call evaluate(left, grid, [x(p) - d], outside, [half(p)])
         call evaluate(right, grid, [x(p) + d], outside, [half(p)])
         do k = 0, grid%elements
            call t%check_close(name//'gradient = dN/dx', at_node(cache, cache%gradient, p, k), &
                               (nodal(right, k) - nodal(left, k))/(2*d), atol=1.0e-6_dp*grid%inv_dx)
         end do
      end do
      ! GIMP: the weights are the box averages of the hat functions (midpoint rule, 4000 points)
      if (kind == shape_ugimp .or. kind == shape_cpgimp) then
         do p = 1, 20
            do k = 0, grid%elements
               call t%check_close(name//'weight = box average of the hat', at_node(cache, cache%weight, p, k), &
                                  box_average(node_x(k + 1), x(p), half(p), grid%dx), atol=1.0e-6_dp)
            end do
         end do
      end if
      ! outside the domain, either side (and NaN)
      call evaluate(left, grid, [grid%origin - h], outside, [lp])
      call t%check(name//'left of the domain is flagged', outside == 1)
      call evaluate(left, grid, [grid%origin + grid%length + h], outside, [lp])
      call t%check(name//'right of the domain is flagged', outside == 1)
      call evaluate(left, grid, [ieee_value(1.0_dp, ieee_quiet_nan)], outside, [lp])
      call t%check(name//'NaN is flagged', outside == 1)
      call t%check(name//'a flagged particle has zero weights', all(left%weight(1, :) == 0.0_dp))
      ! the first particle outside among many (the shape loops find it by an integer minimum), and the
      ! edges of the support: inside by 1e-9 dx is inside, outside by 1e-9 dx is flagged
      d = lowest_inside(kind)*grid%dx
      x = [(node_x(4), i=1, 12)]
      many%kind = kind  ! (a cache is sized by its first use: 12 particles)
      x(7) = grid%origin + d - h
      x(10) = ieee_value(1.0_dp, ieee_quiet_nan)
      call evaluate(many, grid, x, outside, [(lp, i=1, 12)])
      call t%check(name//'the first of two particles outside is named', outside == 7)
      x(7) = grid%origin + d + h
      x(10) = grid%origin + grid%length - d - h
      call evaluate(many, grid, x, outside, [(lp, i=1, 12)])
      call t%check(name//'particles at the edges of the domain by 1e-9 dx are inside', outside == 0)
      x(10) = grid%origin + grid%length - d + h
      call evaluate(many, grid, x, outside, [(lp, i=1, 12)])
      call t%check(name//'right edge of the domain + 1e-9 dx is flagged', outside == 10)
      ! every column of a particle inside the domain names a node of the grid (the operations read and
      ! write all of a particle's columns), at the domain's right edge too, where the weights still sum to 1
      x(10) = grid%origin + grid%length - d - h
      call evaluate(many, grid, x, outside, [(lp, i=1, 12)])
      call t%check(name//'at the right edge of the domain, the columns name nodes of the grid only', &
                   all(many%first >= 0 .and. many%first + many%support - 1 <= grid%elements))
      i = many%first(10)
      call t%check_close(name//'at the right edge of the domain: partition of unity', sum(many%weight(10, :)), 1.0_dp, &
                         atol=1.0e-14_dp)
      call t%check_close(name//'at the right edge of the domain: sum N_I x_I = x', &
                         sum(many%weight(10, :)*node_x(i + 1:i + many%support)), x(10), rtol=1.0e-14_dp)
   end subroutine properties

   !> evaluate_shapes with the GIMP boxes' half-lengths `half`, CPDI's domains x -/+ half, each a domain of
   !> its own (the other shapes ignore them).
   subroutine evaluate(cache, grid, x, outside, half)
      type(shape_cache_t), intent(inout) :: cache
      type(grid_t), intent(in) :: grid
      real(dp), intent(in) :: x(:), half(:)
      integer, intent(out) :: outside
      integer :: p
      cache%half_length = half
      if (cache%kind == shape_cpdi) then
         cache%corner_of = [(2*(p - 1), p=1, size(x))]
         allocate (cache%corners(0:2*size(x) - 1))
         cache%corners(0::2) = x - half
         cache%corners(1::2) = x + half
      end if
      call evaluate_shapes(cache, grid, x, outside)
      if (allocated(cache%corners)) deallocate (cache%corners)
   end subroutine evaluate

   !> CPDI against its closed form: S_I = (N_I(x1) + N_I(x2))/2 from the hat, G_I the mean of dN_I/dx over
   !> [x1, x2] (from the overlaps of the domain with the hat's two slopes); and a domain whose corners lie in
   !> cells more than two apart flagged.
   subroutine cpdi_closed_form(cache, grid, node_x, x, half)
      type(shape_cache_t), intent(in) :: cache
      type(grid_t), intent(in) :: grid
      real(dp), intent(in) :: node_x(:), x(:), half(:)
      type(shape_cache_t) :: long
      integer :: p, k, outside
      do p = 1, 40
         do k = 0, grid%elements
            call t%check_close('cpdi: weight = mean of the hat at the corners', at_node(cache, cache%weight, p, k), &
                               0.5_dp*(hat(node_x(k + 1), x(p) - half(p), grid%dx) + &
                                       hat(node_x(k + 1), x(p) + half(p), grid%dx)), atol=1.0e-14_dp)
            call t%check_close('cpdi: gradient = mean of dN/dx over the domain', at_node(cache, cache%gradient, p, k), &
                               mean_slope(node_x(k + 1), x(p), half(p), grid%dx), atol=1.0e-12_dp*grid%inv_dx)
         end do
      end do
      long%kind = shape_cpdi
      call evaluate(long, grid, [node_x(1) + 3.55_dp*grid%dx, node_x(1) + 3.0_dp*grid%dx], outside, &
                    [1.35_dp*grid%dx, 1.05_dp*grid%dx])
      call t%check('cpdi: corners in cells 2 and 4 (2.7 cells apart) are not stretched', outside == 0 .and. &
                   long%stretched /= 1)
      call t%check('cpdi: ... and touch four nodes', count(long%weight(1, :) > 0.0_dp) == 4)
      call t%check('cpdi: corners in cells 1 and 4 (2.1 cells apart) are stretched', long%stretched == 2)
      call t%check('cpdi: a stretched domain has zero weights', all(long%weight(2, :) == 0.0_dp))
   end subroutine cpdi_closed_form

   !> The hat of the node at xi, at y.
   pure real(dp) function hat(xi, y, dx)
      real(dp), intent(in) :: xi, y, dx
      hat = max(0.0_dp, 1.0_dp - abs(y - xi)/dx)
   end function hat

   !> (1/2l) int_{x-l}^{x+l} dN_I/dx, N_I the hat of the node at xi: dN_I/dx is 1/dx on (xi - dx, xi) and
   !> -1/dx on (xi, xi + dx), so the integral is the lengths of the domain's overlaps with them over dx.
   pure real(dp) function mean_slope(xi, x, l, dx)
      real(dp), intent(in) :: xi, x, l, dx
      real(dp) :: rising, falling
      rising = max(0.0_dp, min(xi, x + l) - max(xi - dx, x - l))
      falling = max(0.0_dp, min(xi + dx, x + l) - max(xi, x - l))
      mean_slope = (rising - falling)/dx/(2*l)
   end function mean_slope

   !> Grid coordinate (in cells from the origin) of the leftmost particle whose support is inside the
   !> grid: the support's half-width less one cell (GIMP with boxes of half-length dx/4).
   real(dp) function lowest_inside(kind)
      integer, intent(in) :: kind
      select case (kind)
      case (shape_ugimp, shape_cpgimp, shape_cpdi)
         lowest_inside = 0.25_dp
      case (shape_bspline2)
         lowest_inside = 0.5_dp
      case (shape_bspline3)
         lowest_inside = 1.0_dp
      case default
         lowest_inside = 0.0_dp
      end select
   end function lowest_inside

   !> inside_range (the shapes' branch-free range test) against the comparison it stands for.
   subroutine range_test()
      real(dp) :: nan, inf, values(11)
      integer :: i
      logical :: expected
      nan = ieee_value(1.0_dp, ieee_quiet_nan)
      inf = ieee_value(1.0_dp, ieee_positive_inf)
      values = [1.0_dp, 3.0_dp, 2.0_dp, nearest(1.0_dp, -1.0_dp), nearest(3.0_dp, 1.0_dp), 0.0_dp, -2.0_dp, inf, -inf, &
                nan, -nan]
      do i = 1, size(values)
         expected = values(i) >= 1.0_dp .and. values(i) <= 3.0_dp
         call t%check('inside_range(s, 1, 3) is 1 exactly when 1 <= s <= 3, s = '//trim(adjustl(str(values(i)))), &
                      (inside_range(values(i), 1.0_dp, 3.0_dp) == 1) .eqv. expected)
      end do
      call t%check('inside_range: +0 is inside [0, 1]', inside_range(0.0_dp, 0.0_dp, 1.0_dp) == 1)
      call t%check('inside_range: -0 counts as outside [0, 1] (as in the fused kernels)', &
                   inside_range(-0.0_dp, 0.0_dp, 1.0_dp) == 0)
      call t%check('inside_range: the largest double is inside [0, huge]', &
                   inside_range(huge(1.0_dp), 0.0_dp, huge(1.0_dp)) == 1)
   end subroutine range_test

   character(len=32) function str(value)
      real(dp), intent(in) :: value
      write (str, '(es12.5)') value
   end function str

   !> (1/2l) int_{x-l}^{x+l} N_I, N_I the hat of the node at xi, by the midpoint rule.
   real(dp) function box_average(xi, x, l, dx)
      real(dp), intent(in) :: xi, x, l, dx
      integer, parameter :: n = 4000
      integer :: j
      real(dp) :: y
      box_average = 0.0_dp
      do j = 1, n
         y = x - l + (j - 0.5_dp)*2*l/n
         box_average = box_average + max(0.0_dp, 1.0_dp - abs(y - xi)/dx)
      end do
      box_average = box_average/n
   end function box_average

   !> values(p, :) (cache%weight or cache%gradient) at node i (0 when particle p does not touch it).
   real(dp) function at_node(cache, values, p, i)
      type(shape_cache_t), intent(in) :: cache
      real(dp), intent(in) :: values(:, :)
      integer, intent(in) :: p, i
      at_node = 0.0_dp
      if (i >= cache%first(p) .and. i < cache%first(p) + cache%support) at_node = values(p, i - cache%first(p) + 1)
   end function at_node

   !> Weight of node i in a one-particle cache.
   real(dp) function nodal(cache, i)
      type(shape_cache_t), intent(in) :: cache
      integer, intent(in) :: i
      nodal = at_node(cache, cache%weight, 1, i)
   end function nodal
end program test_shape_functions
