!> The fused specialisation of USF, USL and MUSL for the paper's bar: any shape function (linear; the
!> wide ones as particles in parts, see mpm_transfer), FLIP, one particle mass and volume, one
!> material, no external force. Each step is one or two fused passes over the particles
!> (mpm_transfer), which also carry the next step's
!> particle-to-grid transfer. The generic path (mpm_schemes over mpm_operations) is the definition;
!> these kernels are chosen automatically where they apply (mpm_simulation) and must agree with it
!> to round-off (test_generic).
module mpm_fused
   use mpm_kinds, only: dp
   use mpm_grid, only: grid_t, assemble_nodes, assemble_and_solve, nodal_velocity, solve_momentum
   use mpm_operations, only: mirror_fold
   use mpm_particles, only: particles_t
   use mpm_shape, only: shape_linear, shape_cpgimp, shape_bspline2, shape_bspline3
   use mpm_schemes, only: scheme_usf, scheme_usl, scheme_musl
   use mpm_transfer, only: pass_totals_t, p2g, fused_pass, pass_usf_stress, pass_usf_move, pass_usl, pass_musl_remap, &
                           pass_musl_stress, merge_totals, fused_box_t, box_cells
   implicit none
   private
   public :: fused_start, fused_step, fused_box_t, fused_shape

contains

   !> Initial mapping: element shares of mass, momentum and (USL, MUSL) stress*volume. With particles
   !> in parts (`box`, and the run's `youngs_modulus`): a USL pass of zero time step, which moves
   !> nothing and maps the parts where they are (x + 0, v + 0, sigma + E 0, J (1 + 0) leave every value
   !> as it is).
   subroutine fused_start(scheme, particles, grid, totals, box, youngs_modulus)
      integer, intent(in) :: scheme
      type(particles_t), intent(inout) :: particles
      type(grid_t), intent(inout) :: grid
      type(pass_totals_t), intent(out) :: totals
      type(fused_box_t), intent(inout), optional :: box
      real(dp), intent(in), optional :: youngs_modulus
      if (present(box)) then
         if (box%parts) then
            if (scheme /= scheme_usl .and. .not. allocated(box%carry)) allocate (box%carry(particles%count))
            if (.not. allocated(box%carry)) allocate (box%carry(0))
            call box_cells(particles, grid, box)
            call fused_pass(pass_usl, particles, grid, 0.0_dp, youngs_modulus, totals, box)
            return
         end if
         ! the hat's passes take it too (no carry), so that no pass allocates one
         if (.not. allocated(box%carry)) allocate (box%carry(0))
      end if
      call p2g(particles, grid, scheme /= scheme_usf, totals)
   end subroutine fused_start

   !> One step; on entry the element shares hold this step's P2G, on exit the next step's.
   !> USF: nodal velocity -> stress update and its internal force -> momentum update -> G2P fused with
   !> the next mass and momentum shares. USL: momentum update -> one pass of G2P, stress update and the
   !> next P2G. MUSL: momentum update -> G2P with the new momentum mapped back -> nodal velocity ->
   !> stress update fused with the next P2G.
   !> With particles in parts (fused_start's `box`) the nodal sums are reflected at a mirrored fixed
   !> end before they are used (mirror_fold, as on the generic path: the wide shapes' grid has a ghost
   !> cell there).
   subroutine fused_step(scheme, particles, grid, dt, youngs_modulus, totals, box)
      integer, intent(in) :: scheme
      type(particles_t), intent(inout) :: particles
      type(grid_t), intent(inout) :: grid
      real(dp), intent(in) :: dt, youngs_modulus
      type(pass_totals_t), intent(out) :: totals
      type(fused_box_t), intent(inout), optional :: box
      type(pass_totals_t) :: stress_totals
      logical :: wide, with_box
      wide = .false.
      with_box = .false.
      if (present(box)) then
         wide = box%parts
         with_box = allocated(box%carry)
      end if
      select case (scheme)
      case (scheme_usf)
         call kinematics()
         call pass(pass_usf_stress, stress_totals)
         if (wide) then
            call solve()
         else ! the force assembled in the solve (mass and momentum are assembled already)
            call solve_momentum(grid, dt, .true.)
         end if
         call pass(pass_usf_move, totals)
         call merge_totals(totals, stress_totals)
      case (scheme_usl)
         call solve()
         call pass(pass_usl, totals)
      case (scheme_musl)
         call solve()
         call pass(pass_musl_remap, totals)
         call kinematics()
         call pass(pass_musl_stress, stress_totals)
         call merge_totals(totals, stress_totals)
      end select
   contains
      !> Nodal mass and momentum (reflected at a mirrored end: wide shapes), then the nodal velocity.
      subroutine kinematics()
         call assemble_nodes(grid, .false.)
         if (wide) call mirror_fold(grid, .true., .false.)
         call nodal_velocity(grid)
      end subroutine kinematics
      !> Nodal mass, momentum and force (reflected: wide shapes), then the momentum update; the hat's
      !> grid has no ghost, and assembles and solves chunk by chunk.
      subroutine solve()
         if (wide) then
            call assemble_nodes(grid, .true.)
            call mirror_fold(grid, .true., .true.)
            call solve_momentum(grid, dt, .false.)
         else
            call assemble_and_solve(grid, dt)
         end if
      end subroutine solve
      !> One fused pass, with the particles' parts when they have some.
      subroutine pass(kind, pass_totals)
         integer, intent(in) :: kind
         type(pass_totals_t), intent(out) :: pass_totals
         if (with_box) then
            call fused_pass(kind, particles, grid, dt, youngs_modulus, pass_totals, box)
         else
            call fused_pass(kind, particles, grid, dt, youngs_modulus, pass_totals)
         end if
      end subroutine pass
   end subroutine fused_step

   !> The fused kernels' description of shape `kind` (mpm_shape's ids): the hat, or a particle in parts
   !> (GIMP's box, fixed or stretched; the B-splines, in two parts or, cubic, three).
   pure function fused_shape(kind) result(box)
      integer, intent(in) :: kind
      type(fused_box_t) :: box
      box%parts = kind /= shape_linear
      box%stretch = kind == shape_cpgimp
      box%spline = kind == shape_bspline2 .or. kind == shape_bspline3
      box%cubic = kind == shape_bspline3
   end function fused_shape
end module mpm_fused
