!> Properties every shape function must have, checked for each shape on a grid with empty
!> margin cells: partition of unity, gradients summing to zero, linear fields reproduced exactly
!> (sum N_I x_I = x and sum dN_I x_I = 1), weights continuous as a particle crosses a node, and
!> particles outside the domain flagged.
program test_shape
   use mpm_kinds, only: dp
   use mpm_errors, only: error_t
   use mpm_grid, only: grid_t, grid_init
   use mpm_shape, only: shape_cache_t, evaluate_shapes, shape_linear, shape_name
   use mpm_testing, only: tester_t
   implicit none
   type(tester_t) :: t
   integer, parameter :: shapes(1) = [shape_linear]
   integer :: s
   t%name = 'test_shape'
   do s = 1, size(shapes)
      call properties(shapes(s))
   end do
   call t%finish()

contains

   subroutine properties(kind)
      integer, intent(in) :: kind
      type(grid_t) :: grid
      type(shape_cache_t) :: cache, left, right
      type(error_t), allocatable :: error
      real(dp), allocatable :: x(:), node_x(:)
      real(dp) :: h
      integer :: p, k, outside, n
      character(len=:), allocatable :: name
      name = shape_name(kind)//': '
      call grid_init(grid, 7, 3.5_dp, 1.0_dp, error, margin=3, element_shares=.false.)
      node_x = [(grid%origin + k*grid%dx, k=0, grid%elements)]
      n = 997
      allocate (x(n))
      call random_number(x)
      x = grid%origin + x*grid%length
      cache%kind = kind
      call evaluate_shapes(cache, grid, x, outside)
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
      call evaluate_shapes(left, grid, [node_x(5) - h], outside)
      call evaluate_shapes(right, grid, [node_x(5) + h], outside)
      call t%check_close(name//'weight of the crossed node continuous', nodal(left, 4), nodal(right, 4), atol=1.0e-8_dp)
      call t%check_close(name//'weight of the next node continuous', nodal(left, 5), nodal(right, 5), atol=1.0e-8_dp)
      call t%check_close(name//'weight of the previous node continuous', nodal(left, 3), nodal(right, 3), atol=1.0e-8_dp)
      ! outside the domain, either side (and NaN)
      call evaluate_shapes(left, grid, [grid%origin - h], outside)
      call t%check(name//'left of the domain is flagged', outside == 1)
      call evaluate_shapes(left, grid, [grid%origin + grid%length + h], outside)
      call t%check(name//'right of the domain is flagged', outside == 1)
   end subroutine properties

   !> Weight of node i in a one-particle cache (0 when the particle does not touch it).
   real(dp) function nodal(cache, i)
      type(shape_cache_t), intent(in) :: cache
      integer, intent(in) :: i
      nodal = 0.0_dp
      if (i >= cache%first(1) .and. i < cache%first(1) + cache%support) nodal = cache%weight(1, i - cache%first(1) + 1)
   end function nodal
end program test_shape
