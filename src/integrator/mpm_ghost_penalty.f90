!> The ghost penalty of the implicit integrators (`ghost_penalty` = gamma > 0): a remedy for the small
!> cut cells of MPM. Where a body ends inside a cell, a node whose basis function barely overlaps it
!> gets a tiny mass and (for the wide shapes, whose gradients vanish with their weights) a tiny stiffness:
!> its row of the tangent is nearly zero, the tangent ill-conditioned, and the node's increment is
!> decided by round-off. The ghost penalty of the unfitted finite element methods (Burman, "Ghost penalty",
!> C. R. Math. 348, 2010, doi:10.1016/j.crma.2010.10.006; for elastic waves Sticko, Ludvigsson and Kreiss,
!> Adv. Comput. Math. 46:45, 2020; in MPM Coombs, "Ghost stabilisation of the Material Point Method for
!> stable quasi-static and dynamic analysis of large deformation problems", Int. J. Numer. Methods Eng.,
!> 2023, and the ghostPenalty function of the AMPLE code, Coombs and Augarde 2020,
!> doi:10.1016/j.advengsoft.2019.102748; see docs/theory.md) penalises the jump of the highest derivative
!> of the displacement increment across the faces between a cut cell and its filled neighbour, which ties
!> the cut cell's polynomial to its neighbour's: a penalty that vanishes on the polynomials the grid
!> represents (consistent) and gives the nearly empty node a row of its own.
!> In 1-D a "face" is a knot of the grid's basis, and the jump of the p-th derivative of a degree-p spline
!> u = sum_I N_I u_I at a knot is the (p+1)-th difference of the coefficients over dx^p: hat and GIMP
!> (p = 1) (u_{s} - 2 u_{s+1} + u_{s+2})/dx at node s + 1; quadratic B-splines (p = 2, knots at cell
!> midpoints) (-u_s + 3 u_{s+1} - 3 u_{s+2} + u_{s+3})/dx^2; cubic B-splines (p = 3, knots at the nodes)
!> (u_s - 4 u_{s+1} + 6 u_{s+2} - 4 u_{s+3} + u_{s+4})/dx^3. The penalty energy gamma E dx^(2p-1) jump^2/2
!> per knot adds the stiffness (gamma E/dx) d d^T on the stencil's nodes (d: the difference coefficients),
!> dimensionless gamma, E the Young's modulus of the boundary cell's material. Its stencil has p + 2 nodes,
!> one more than a particle's support: the tangent's bandwidth grows by one when the penalty is on.
!> Knots penalised: at every free end of a body, the knot between its cut span (the last span a particle
!> reaches: a cell, or for the quadratic B-splines a span centred on a node) and the body's span next to it
!> (find_ghost_knots). A mirrored fixed end is not cut (its ghost cells hold the body's image).
module mpm_ghost_penalty
   use mpm_kinds, only: dp
   use mpm_grid, only: grid_t
   use mpm_shape, only: shape_cache_t, shape_ugimp, shape_cpgimp, shape_bspline2, shape_bspline3
   implicit none
   private
   public :: ghost_knots_t, find_ghost_knots, ghost_stencil

   !> The knots penalised in one step.
   type :: ghost_knots_t
      integer :: count = 0
      integer, allocatable :: start(:)        !< the first node of each knot's stencil
      real(dp), allocatable :: stiffness(:)   !< gamma E/dx of each (N/m per unit area)
      real(dp), allocatable :: stencil(:)     !< the difference coefficients d (p + 2 of them)
   end type ghost_knots_t

contains

   !> The (p+1)-th difference coefficients of shape `kind` (p its polynomial degree).
   pure function ghost_stencil(kind) result(d)
      integer, intent(in) :: kind
      real(dp), allocatable :: d(:)
      select case (kind)
      case (shape_bspline2)
         d = [-1.0_dp, 3.0_dp, -3.0_dp, 1.0_dp]
      case (shape_bspline3)
         d = [1.0_dp, -4.0_dp, 6.0_dp, -4.0_dp, 1.0_dp]
      case default ! hat and GIMP (the grid's basis is the hat)
         d = [1.0_dp, -2.0_dp, 1.0_dp]
      end select
   end function ghost_stencil

   !> The knots to penalise for particles at `x` of lengths (volumes per unit area) `volume`, each with the
   !> stiffness gamma E/dx of the material of the boundary span's particle (`modulus`, one per particle).
   !> A body is a run of spans its material overlaps (each particle's length [x - V/2, x + V/2], by more
   !> than 1e-9 dx: the quadratic B-splines' spans, centred on the nodes, have their edges at the cell
   !> centres where particles of one per cell sit, so the particles' centres alone leave spans inside a
   !> body empty). Its cut span at a free end is the last span a particle reaches with its basis functions
   !> (its centre; for GIMP its box [x - l_p, x + l_p]): the span whose outermost node is the nearly empty
   !> one. The knot between the cut span and the body's span next to it is penalised when every node of
   !> its stencil carries mass (an empty node's increment is held at zero: a penalty through it would tie
   !> the body to a node outside the discrete space).
   subroutine find_ghost_knots(cache, grid, x, volume, modulus, gamma, knots)
      type(shape_cache_t), intent(in) :: cache
      type(grid_t), intent(in) :: grid
      real(dp), intent(in) :: x(:), volume(:), modulus(:), gamma
      type(ghost_knots_t), intent(inout) :: knots
      real(dp), parameter :: overlap = 1.0e-9_dp
      logical, allocatable :: material(:), reached(:)
      real(dp), allocatable :: span_modulus(:)
      real(dp) :: shift, reach
      integer :: spans, p, s, r, offset, width, lo, hi
      logical :: gimp
      knots%stencil = ghost_stencil(cache%kind)
      width = size(knots%stencil)
      ! span s: cell [x_s, x_{s+1}] (hat, GIMP, cubic) or [x_s - dx/2, x_s + dx/2] (quadratic)
      shift = merge(0.5_dp, 0.0_dp, cache%kind == shape_bspline2)
      gimp = cache%kind == shape_ugimp .or. cache%kind == shape_cpgimp
      spans = grid%elements + 1
      allocate (material(0:spans - 1), reached(0:spans - 1), span_modulus(0:spans - 1))
      material = .false.
      reached = .false.
      span_modulus = 0.0_dp
      do p = 1, size(x)
         call mark(material, 0.5_dp*volume(p))
         reach = 0.0_dp
         if (gimp) reach = cache%half_length(p)
         call mark(reached, reach)
      end do
      ! the image beyond a mirrored fixed end fills its ghost spans
      if (grid%mirror) material(0:grid%ghost - 1) = .true.
      if (grid%mirror_right >= 0) material(grid%mirror_right + merge(1, 0, shift > 0.0_dp):) = .true.
      ! the stencil's first node for the knot between spans s - 1 and s
      offset = merge(1, 2, width == 3)
      if (.not. allocated(knots%start)) allocate (knots%start(0), knots%stiffness(0))
      knots%count = 0
      do s = 0, spans - 1
         if (.not. material(s)) cycle
         if (s < spans - 1) then ! a free end to the right: the last reached span r of the body
            if (.not. material(s + 1)) then
               r = s
               do while (r > 0 .and. .not. reached(r))
                  if (.not. material(r - 1)) exit
                  r = r - 1
               end do
               if (r > 0 .and. reached(r)) then
                  if (material(r - 1)) call add(r - offset, span_modulus(r))
               end if
            end if
         end if
         if (s > 0) then ! a free end to the left: the first reached span r; the knot between r and r + 1
            if (.not. material(s - 1)) then
               r = s
               do while (r < spans - 1 .and. .not. reached(r))
                  if (.not. material(r + 1)) exit
                  r = r + 1
               end do
               if (r < spans - 1 .and. reached(r)) then
                  if (material(r + 1)) call add(r + 1 - offset, span_modulus(r))
               end if
            end if
         end if
      end do
   contains
      !> Mark the spans [x(p) - half, x(p) + half] overlaps (the one holding x(p) when half = 0).
      subroutine mark(spans_of, half)
         logical, intent(inout) :: spans_of(0:)
         real(dp), intent(in) :: half
         if (half > 0.0_dp) then
            lo = floor((x(p) - half - grid%origin)*grid%inv_dx + shift + overlap)
            hi = floor((x(p) + half - grid%origin)*grid%inv_dx + shift - overlap)
         else
            lo = floor((x(p) - grid%origin)*grid%inv_dx + shift)
            hi = lo
         end if
         lo = max(lo, 0)
         hi = min(hi, spans - 1)
         if (lo > hi) return
         spans_of(lo:hi) = .true.
         span_modulus(lo:hi) = modulus(p)
      end subroutine mark
      subroutine add(first, e)
         integer, intent(in) :: first
         real(dp), intent(in) :: e
         if (first < 0 .or. first + width - 1 > grid%elements) return
         if (any(grid%mass(first:first + width - 1) <= grid%empty_mass)) return
         knots%count = knots%count + 1
         if (knots%count > size(knots%start)) then
            knots%start = [knots%start, 0, 0]
            knots%stiffness = [knots%stiffness, 0.0_dp, 0.0_dp]
         end if
         knots%start(knots%count) = first
         knots%stiffness(knots%count) = gamma*e*grid%inv_dx
      end subroutine add
   end subroutine find_ghost_knots
end module mpm_ghost_penalty
