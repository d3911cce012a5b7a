!> The shape layer: for every particle, the nodes it touches, their weights N_I(x_p) and gradients
!> dN_I/dx(x_p), evaluated once per step at the start-of-step positions and kept in a shape_cache_t
!> that the generic operations (mpm_operations) read. A shape function is one module plus one case
!> below; every shape passes the same property tests (test_shape_functions):
!>   linear    the hat functions (mpm_shape_linear)
!>   ugimp     uniform GIMP, box half-length l_p0 = dx/(2 ppc) (mpm_shape_gimp)
!>   cpgimp    contiguous-particle GIMP, l_p = l_p0 J_p (mpm_shape_gimp)
!>   bspline2  quadratic B-splines (mpm_shape_bspline)
!>   bspline3  cubic B-splines (mpm_shape_bspline)
!>   cpdi      convected particle domains: the hat averaged over each particle's domain, whose corners move
!>             with the grid (mpm_shape_cpdi)
!> Shapes wider than the hat need one grid cell beyond each end of the body (shape_extra_cells); at
!> a fixed end that cell is a mirror ghost (mpm_grid, mirror_fold).
!> The cache also carries the velocity transfer of G2P (flip, pic, blend, apic, xpic, fmpm, asflip) and the
!> formulation (updated or total Lagrangian: in the total one the weights are evaluated once, at the
!> reference positions): the operations read them from it.
module mpm_shape
   use mpm_kinds, only: dp
   use mpm_names, only: name_id, id_name
   use mpm_grid, only: grid_t
   use mpm_state, only: state_t
   use mpm_shape_linear, only: linear_support, linear_shapes
   use mpm_shape_gimp, only: gimp_support, gimp_shapes
   use mpm_shape_bspline, only: bspline2_support, bspline3_support, bspline2_shapes, bspline3_shapes
   use mpm_shape_cpdi, only: cpdi_support, cpdi_shapes
   implicit none
   private
   public :: shape_cache_t, shape_linear, shape_ugimp, shape_cpgimp, shape_bspline2, shape_bspline3, shape_cpdi, all_shapes
   public :: shape_support, evaluate_shapes, shape_name, shape_id, shape_extra_cells, known_shapes
   public :: transfer_flip, transfer_pic, transfer_blend, transfer_apic, transfer_xpic, transfer_fmpm, transfer_asflip
   public :: all_transfers, transfer_id, transfer_name, known_transfers
   public :: formulation_updated, formulation_total, formulation_id, known_formulations
   public :: sync_cache

   !> Shape function ids, in the order of their names in known_shapes (mpm_names).
   integer, parameter :: shape_linear = 1, shape_ugimp = 2, shape_cpgimp = 3, shape_bspline2 = 4, shape_bspline3 = 5, &
                         shape_cpdi = 6
   integer, parameter :: all_shapes(6) = [shape_linear, shape_ugimp, shape_cpgimp, shape_bspline2, shape_bspline3, &
                                          shape_cpdi]
   character(len=*), parameter :: known_shapes = 'linear, ugimp, cpgimp, bspline2, bspline3, cpdi'
   !> Velocity transfer ids (G2P; in the order of known_transfers): FLIP v += dt sum N a; PIC v = sum N v; their blend; APIC
   !> ([Jiang 2015] in docs/theory.md: PIC plus a per-particle velocity gradient carried into the next P2G);
   !> XPIC(m), FMPM(k) and ASFLIP (mpm_xpic, mpm_fmpm, mpm_asflip; docs/theory.md, The cures).
   integer, parameter :: transfer_flip = 1, transfer_pic = 2, transfer_blend = 3, transfer_apic = 4, &
                         transfer_xpic = 5, transfer_fmpm = 6, transfer_asflip = 7
   integer, parameter :: all_transfers(7) = [transfer_flip, transfer_pic, transfer_blend, transfer_apic, &
                                             transfer_xpic, transfer_fmpm, transfer_asflip]
   character(len=*), parameter :: known_transfers = 'flip, pic, blend, apic, xpic, fmpm, asflip'
   !> The formulations (in the order of known_formulations): updated Lagrangian (the weights at the
   !> particles' positions each step) and total Lagrangian ([de Vaucorbeil 2020]: the weights and
   !> gradients at the reference positions, once).
   integer, parameter :: formulation_updated = 1, formulation_total = 2
   character(len=*), parameter :: known_formulations = 'updated, total'

   !> Weights and gradients of every particle: node first(p) + k - 1 gets weight(p, k), gradient(p, k)
   !> (particle index first, so that the operations' loops over particles read them contiguously).
   type :: shape_cache_t
      integer :: kind = shape_linear
      integer :: support = 0
      integer, allocatable :: first(:)
      real(dp), allocatable :: weight(:, :), gradient(:, :)
      !> Scratch space of the operations, one value per particle each (gathered nodal values).
      real(dp), allocatable :: work(:, :)
      !> The velocity transfer of G2P, and the FLIP share of the blend (1 = FLIP, 0 = PIC), the order of XPIC
      !> and FMPM, ASFLIP's alpha.
      integer :: transfer = transfer_flip
      real(dp) :: flip_fraction = 1.0_dp
      integer :: order = 1
      real(dp) :: alpha = 0.0_dp
      !> Total Lagrangian: the weights and gradients are those of the reference positions, evaluated once
      !> (and `evaluated` then says they are).
      logical :: total = .false., evaluated = .false.
      !> Grid-sized scratch of the transfers (node index 0..cells, a column each), allocated by the transfer
      !> that uses it (XPIC, FMPM, ASFLIP).
      real(dp), allocatable :: grid_work(:, :)
      !> Each particle's J at the start of the step (ASFLIP).
      real(dp), allocatable :: start_volume_ratio(:)
      !> The CPDI domains' corners (0-based; particle p spans corners(corner_of(p)) .. corners(corner_of(p) + 1))
      !> and the first particle whose domain is longer than the shape's nodes cover (0: none).
      real(dp), allocatable :: corners(:)
      integer, allocatable :: corner_of(:)
      integer :: stretched = 0
      !> The particles' box half-lengths (GIMP only), set by the caller before evaluate_shapes.
      real(dp), allocatable :: half_length(:)
      !> Start-of-step positions (APIC only: the affine term of P2G needs x_I - x_p after G2P moved x).
      real(dp), allocatable :: position(:)
   end type shape_cache_t

contains

   pure function shape_name(kind) result(name)
      integer, intent(in) :: kind
      character(len=:), allocatable :: name
      name = id_name(kind, known_shapes)
   end function shape_name

   !> Id of a shape name (0 if unknown; the configuration is validated before).
   pure integer function shape_id(name)
      character(len=*), intent(in) :: name
      shape_id = name_id(name, known_shapes)
   end function shape_id

   pure function transfer_name(kind) result(name)
      integer, intent(in) :: kind
      character(len=:), allocatable :: name
      name = id_name(kind, known_transfers)
   end function transfer_name

   !> Id of a transfer name (0 if unknown).
   pure integer function transfer_id(name)
      character(len=*), intent(in) :: name
      transfer_id = name_id(name, known_transfers)
   end function transfer_id

   !> Nodes per particle of shape `kind`.
   pure integer function shape_support(kind)
      integer, intent(in) :: kind
      select case (kind)
      case (shape_linear)
         shape_support = linear_support
      case (shape_ugimp, shape_cpgimp)
         shape_support = gimp_support
      case (shape_bspline2)
         shape_support = bspline2_support
      case (shape_bspline3)
         shape_support = bspline3_support
      case (shape_cpdi)
         shape_support = cpdi_support
      case default
         shape_support = 0
      end select
   end function shape_support

   !> Grid cells a shape needs beyond an end of the body besides the hat's: its support radius (1 for
   !> the hat, 1 + l_p/dx for GIMP, 3/2 and 2 for the B-splines) rounded up, less one. CPDI's weights are
   !> the hat's at the domain's corners, which stay inside the body's cells and its margin: none.
   pure integer function shape_extra_cells(kind)
      integer, intent(in) :: kind
      shape_extra_cells = merge(0, 1, kind == shape_linear .or. kind == shape_cpdi)
   end function shape_extra_cells

   !> Id of a formulation name (0 if unknown).
   pure integer function formulation_id(name)
      character(len=*), intent(in) :: name
      formulation_id = name_id(name, known_formulations)
   end function formulation_id

   !> Fill `cache` for positions x (allocating it on first use); `outside` = first particle outside
   !> the grid domain (its support not inside the grid), 0 if none. GIMP needs the particles' box
   !> half-lengths in cache%half_length, CPDI the domains' corners in cache%corners (x is then the
   !> domains' centres).
   subroutine evaluate_shapes(cache, grid, x, outside)
      type(shape_cache_t), intent(inout) :: cache
      type(grid_t), intent(in) :: grid
      real(dp), intent(in), contiguous :: x(:)
      integer, intent(out) :: outside
      if (.not. allocated(cache%first)) then
         cache%support = shape_support(cache%kind)
         allocate (cache%first(size(x)), cache%weight(size(x), cache%support), cache%gradient(size(x), cache%support))
      end if
      select case (cache%kind)
      case (shape_linear)
         call linear_shapes(grid%origin, grid%inv_dx, grid%elements, x, cache%first, cache%weight, cache%gradient, outside)
      case (shape_ugimp, shape_cpgimp)
         call gimp_shapes(grid%origin, grid%inv_dx, grid%elements, x, cache%half_length, cache%first, cache%weight, &
                          cache%gradient, outside)
      case (shape_bspline2)
         call bspline2_shapes(grid%origin, grid%inv_dx, grid%elements, x, cache%first, cache%weight, cache%gradient, &
                              outside)
      case (shape_bspline3)
         call bspline3_shapes(grid%origin, grid%inv_dx, grid%elements, x, cache%first, cache%weight, cache%gradient, &
                              outside)
      case (shape_cpdi)
         call cpdi_shapes(grid%origin, grid%inv_dx, grid%elements, cache%corners, cache%corner_of, cache%first, &
                          cache%weight, cache%gradient, outside, cache%stretched)
      end select
      if (cache%transfer == transfer_apic) then
         if (.not. allocated(cache%position)) allocate (cache%position(size(x)))
         cache%position = x
      end if
   end subroutine evaluate_shapes

   !> What a shape cache carries from one step to the next, to or from `state` (under cache.*, as
   !> state%saving says), for a checkpoint: the weights of a total Lagrangian run (evaluated once), the
   !> CPDI corners, the transfers' grid fields.
   subroutine sync_cache(state, cache)
      type(state_t), intent(inout) :: state
      type(shape_cache_t), intent(inout) :: cache
      call state%sync('cache.first', cache%first)
      call state%sync('cache.weight', cache%weight)
      call state%sync('cache.gradient', cache%gradient)
      call state%sync('cache.work', cache%work)
      call state%sync('cache.evaluated', cache%evaluated)
      call state%sync('cache.grid_work', cache%grid_work)
      call state%sync('cache.start_volume_ratio', cache%start_volume_ratio)
      call state%sync('cache.corners', cache%corners)
      call state%sync('cache.corner_of', cache%corner_of)
      call state%sync('cache.stretched', cache%stretched)
      call state%sync('cache.half_length', cache%half_length)
      call state%sync('cache.position', cache%position)
   end subroutine sync_cache
end module mpm_shape
