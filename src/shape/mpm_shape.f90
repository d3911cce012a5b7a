!> The shape layer: for every particle, the nodes it touches, their weights N_I(x_p) and gradients
!> dN_I/dx(x_p), evaluated once per step at the start-of-step positions and kept in a shape_cache_t
!> that the generic operations (mpm_operations) read. A shape function is one module (today
!> mpm_shape_linear) plus one case below; every shape passes the same property tests (test_shape).
module mpm_shape
   use mpm_kinds, only: dp
   use mpm_grid, only: grid_t
   use mpm_shape_linear, only: linear_support, linear_shapes
   implicit none
   private
   public :: shape_cache_t, shape_linear, shape_support, evaluate_shapes, shape_name

   !> Shape function ids.
   integer, parameter :: shape_linear = 1

   !> Weights and gradients of every particle: node first(p) + k - 1 gets weight(p, k), gradient(p, k)
   !> (particle index first, so that the operations' loops over particles read them contiguously).
   type :: shape_cache_t
      integer :: kind = shape_linear
      integer :: support = 0
      integer, allocatable :: first(:)
      real(dp), allocatable :: weight(:, :), gradient(:, :)
      !> Scratch space of the operations, one value per particle each (gathered nodal values).
      real(dp), allocatable :: work(:, :)
   end type shape_cache_t

contains

   pure function shape_name(kind) result(name)
      integer, intent(in) :: kind
      character(len=:), allocatable :: name
      select case (kind)
      case (shape_linear)
         name = 'linear'
      case default
         name = 'unknown'
      end select
   end function shape_name

   !> Nodes per particle of shape `kind`.
   pure integer function shape_support(kind)
      integer, intent(in) :: kind
      select case (kind)
      case (shape_linear)
         shape_support = linear_support
      case default
         shape_support = 0
      end select
   end function shape_support

   !> Fill `cache` for positions x (allocating it on first use); `outside` = first particle outside
   !> the grid domain, 0 if none.
   subroutine evaluate_shapes(cache, grid, x, outside)
      type(shape_cache_t), intent(inout) :: cache
      type(grid_t), intent(in) :: grid
      real(dp), intent(in) :: x(:)
      integer, intent(out) :: outside
      if (.not. allocated(cache%first)) then
         cache%support = shape_support(cache%kind)
         allocate (cache%first(size(x)), cache%weight(size(x), cache%support), cache%gradient(size(x), cache%support))
      end if
      select case (cache%kind)
      case (shape_linear)
         call linear_shapes(grid%origin, grid%inv_dx, grid%elements, x, cache%first, cache%weight, cache%gradient, outside)
      end select
   end subroutine evaluate_shapes
end module mpm_shape
