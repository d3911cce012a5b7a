!> The implicit integrators (`&discretisation integrator = 'implicit' | 'quasi_static'`): the step is
!> solved on the grid by Newton-Raphson on the nodal displacement increments, with the consistent tangent
!> factored by a banded LU (mpm_banded), and the particles are updated from the converged grid
!> solution. After Guilkey and Weiss, "Implicit time integration for the material point method:
!> quantitative and algorithmic comparisons with the finite element method", Int. J. Numer. Methods Eng.
!> 57, 2003, doi:10.1002/nme.729; Sulsky and Kaul, "Implicit dynamics in the material-point method",
!> Comput. Methods Appl. Mech. Eng. 193, 2004, doi:10.1016/j.cma.2003.12.011; Charlton, Coombs and
!> Augarde, "iGIMP: an implicit generalised interpolation material point method for large
!> deformations", Comput. Struct. 190, 2017, doi:10.1016/j.compstruc.2017.05.004; Coombs and Augarde,
!> "AMPLE: a material point learning environment", Adv. Eng. Softw. 139, 2020,
!> doi:10.1016/j.advengsoft.2019.102748 (docs/theory.md, Implicit and quasi-static integration).
!>
!> A step from t_n to t_{n+1} = t_n + dt, the grid being the step's reference configuration (updated
!> Lagrangian: it moves with the body during the step and is reset after it):
!>   P2G     lumped mass m_I, momentum p_I (the explicit schemes' P2G), v_I = p_I/m_I, and the
!>           acceleration that balances the state at t_n, m_I a_I = f_ext(t_n) - f_int(sigma_n) (+ the
!>           drive's reaction of the last step: the grid is fixed in space, its nodes keep their identity);
!>   unknown the increment du_I, written du = dt v + e (e the part due to acceleration, carried as the
!>           unknown so that the inertia 4 m e/dt^2 is formed without the cancellation of du - dt v);
!>   Newmark trapezoidal rule (beta = 1/4, gamma = 1/2; Newmark 1959): a_{n+1} = 4 e/dt^2 - a_n,
!>           v_{n+1} = v_n + 2 e/dt; unconditionally stable, second order, and it conserves the energy of
!>           a linear system exactly;
!>   balance R(e) = M a_{n+1} + f_int(du) - f_ext(t_{n+1}) = 0 with f_int,I = sum_p dN_Ip sigma_p(d eps_p) V_p^n,
!>           d eps_p = sum_J dN_Jp du_J, the shape functions and volumes of the step's start: in 1-D with
!>           unit area the first Piola-Kirchhoff stress relative to that configuration is the Cauchy
!>           stress, so this is the current configuration's internal force exactly (the grid moving with
!>           the body); the stress is the law's over the finite increment (mpm_material, law_stress);
!>   tangent K = 4 M/dt^2 + sum_p dN_I (d sigma/d eps) dN_J V_p^n: the consistent tangent, whose
!>           spatial form is the material part (F d sigma/dF - sigma) plus the geometric part sigma,
!>           both times dN/dx dN/dx dv in the current configuration (F = 1 + d eps); banded with the
!>           shape's support - 1 sub- and super-diagonals;
!>   Newton  K delta = -R, e += delta, until |R| <= newton_tolerance |forces|, |forces| the norm of the
!>           node-wise sums of the magnitudes of the terms balanced (inertia, every particle's force
!>           share, external force, penalty): the scale of the round-off in R, so the tolerance is
!>           reachable down to a few eps;
!>   affine  the linear law (sigma = sigma_n + E J_n d eps) makes R exactly affine in e: f(sigma_n) and
!>           S = sum_p dN_I E J_n V_p^n dN_J are formed once at the step's start (affine_start) and every
!>           residual is f(sigma_n) + S du + the node-wise terms, without a pass over the particles
!>           (docs/theory.md, The affine residual of the linear law); hencky's on the hat with FLIP per cell:
!>           a cell's particles share their strain increment, so their stresses sigma_n + E ln(1 + d eps)
!>           sum to F + H ln(1 + d eps) with F, H summed at the step's start, one logarithm a cell
!>           (hencky_cells; docs/theory.md, Hencky's residual per cell); the other laws' residual is a pass;
!>   G2P     v_p by the run's transfer from v_{n+1} (FLIP: v_p += sum N (v_{n+1} - v_n)), x_p += sum_I N_Ip
!>           du_I, and the law's state update by d eps_p (update_material_finite).
!> Mass: lumped by default (the row sums, the explicit schemes' P2G unchanged, a diagonal that needs no
!> solve for v_n and a_n, and no coupling to the nearly empty nodes at a body's edge, whose consistent-mass
!> rows are nearly zero); `mass = 'consistent'` uses M_IJ = sum_p m_p N_Ip N_Jp (same band), with
!> M v_n = p and M a_n = f solved.
!> Quasi-static: equilibrium f_int(du) = lambda_k f_ext under the load factor lambda_k = k/load_steps,
!> Newton per increment (no inertia; the scene's fixed nodes hold the body), the particles at rest.
!> Fixed nodes and empty nodes (no mass) are held (du = 0); the mirror ghosts of a fixed end are their
!> partner reflected (du = -du(partner)), folded into the partner's row (T^T K T, bandwidth kept); a
!> scene's drive (mpm_scene, drive_t) moves its nodes at the drive velocity over the whole step (du = V dt,
!> v_{n+1} = V) and its point constraint sum_k w_k v_{n+1,k} = V is a Lagrange multiplier (a bordered
!> system solved with two right-hand sides of the same factors).
module mpm_implicit
   use, intrinsic :: ieee_arithmetic, only: ieee_is_finite, ieee_value, ieee_quiet_nan
   use mpm_kinds, only: dp, i8
   use mpm_names, only: name_id
   use mpm_settings, only: settings_t
   use mpm_grid, only: grid_t
   use mpm_particles, only: particles_t
   use mpm_shape, only: shape_cache_t, shape_linear, transfer_flip
   use mpm_lanes, only: block_size, lanes, add_lanes, lane_total
   use mpm_loads, only: loads_t, drive_t
   use mpm_stepper, only: stepper_stop_t
   use mpm_schemes, only: generic_stepper_t, generic_sync_state
   use mpm_state, only: state_t
   use mpm_pass_totals, only: pass_totals_t
   use mpm_operations, only: locate_particles, p2g_mass_momentum, nodal_velocities, mirror_fold, g2p
   use mpm_material, only: material_t, law_stress_stiffness, update_material_finite, law_linear, law_hencky, &
                           log_one_plus
   use mpm_material_elastic, only: linear_update_on, linear_update_each_on
   use mpm_banded, only: banded_t, banded_init, banded_zero, banded_add, banded_factor, banded_solve, &
                         banded_solve_negated, banded_rcond, banded_multiply, banded_pivot_ratio
   use mpm_ghost_penalty, only: ghost_knots_t, find_ghost_knots
   implicit none
   private
   public :: implicit_t, integrator_explicit, integrator_implicit, integrator_quasi_static, integrator_id, &
             known_integrators
   public :: implicit_init, implicit_advance, implicit_report, prepare_step, assemble_system, newton_solve
   public :: implicit_stepper_t
   public :: series_logarithms, series_limit, tangent_hat, tangent_factor_hat

   !> Integrator ids.
   integer, parameter :: integrator_explicit = 0, integrator_implicit = 1, integrator_quasi_static = 2
   !> Their names, in the order of the ids (mpm_names).
   character(len=*), parameter :: known_integrators = 'explicit, implicit, quasi_static'
   !> Mass matrices.
   integer, parameter :: mass_lumped = 1, mass_consistent = 2
   !> The round-off floor of the residual ("the tolerance meets the floor"): the increments du carry an
   !> absolute round-off of eps |du| (and LU's solution one of eps |K| |du|), and so the strains
   !> d eps = sum dN du one of eps sum |dN du|: where a stiff body moves nearly rigidly (|du|/dx far above
   !> its strains, as the stiff segment of a composite bar does) the residual cannot fall below about
   !> eps sum_J |K_IJ| |du_J|, which can exceed newton_tolerance times the forces. A step whose |R| is within
   !> floor_ulps eps of that (im%roundoff) is converged at its floor (counted: newton_floor_steps).
   real(dp), parameter :: floor_ulps = 64.0_dp
   !> ghost_penalty = -1 (the default): this for the shapes whose gradient vanishes with their weight at the
   !> edge of their support (GIMP, B-splines: a nearly empty node's row of the tangent is nearly zero; the
   !> quasi-static column's B-spline runs blow up without it, studies/implicit), none for the hat (its
   !> nearly empty node keeps the stiffness of dN = 1/dx: the tangent's reciprocal condition stays >= 0.2).
   real(dp), parameter :: automatic_ghost_penalty = 0.1_dp
   !> The largest |x| log_one_plus_series takes (2^-7: a strain increment of 0.8 % in a step).
   real(dp), parameter :: series_limit = 2.0_dp**(-7)
   !> Halvings of a Newton step that does not reduce |R| (a backtracking line search).
   integer, parameter :: max_halvings = 10
   !> Room for the relative residuals of this many solves a step, doubled when a step needs more.
   integer, parameter :: initial_residuals = 32

   !> Everything an implicit run carries (nothing of it exists in an explicit run): the options, the
   !> Newton statistics, the step's grid and particle workspace and the banded matrices.
   type :: implicit_t
      integer :: kind = integrator_implicit
      integer :: mass = mass_lumped
      real(dp) :: tolerance = 1.0e-10_dp
      integer :: max_iterations = 25
      real(dp) :: ghost_penalty = 0.0_dp
      ! statistics over the run
      integer :: steps = 0               !< steps solved
      integer :: solves = 0              !< linear solves over them
      integer :: most_solves = 0         !< the most of one step
      real(dp) :: min_rcond = huge(1.0_dp)  !< smallest reciprocal condition number (1-norm) met
      real(dp) :: min_pivot_ratio = huge(1.0_dp)  !< smallest |U_jj|/max |U_ii| of the LU factors met
      integer :: floor_steps = 0         !< steps accepted at the residual's round-off floor (above tolerance)
      integer :: halvings = 0            !< Newton steps halved by the line search, in all
      real(dp) :: floor_residual = 0.0_dp   !< the largest relative residual accepted so
      ! the last step
      integer :: iterations = 0          !< its linear solves
      !> its relative residual before each solve (0:iterations; grown as a step needs, never sized by
      !> max_iterations: a cap of 2^31 - 1 once allocated 17 GB for steps of 2 solves)
      real(dp), allocatable :: residuals(:)
      logical :: failed = .false.        !< it did not converge (the run stops: status_newton)
      real(dp) :: failed_residual = 0.0_dp
      integer :: singular_node = -1      !< >= 0: the tangent was singular there (an exactly zero pivot)
      !> the singular matrix was the consistent mass matrix (its node: singular_node), not the tangent
      logical :: singular_mass = .false.
      ! the step's data on the nodes 0..elements
      real(dp) :: dt = 0.0_dp
      integer, allocatable :: master(:)  !< the node whose unknown a node takes (itself if free; -1 held)
      real(dp), allocatable :: sign(:)   !< +1, or -1 for a mirror ghost
      logical, allocatable :: prescribed(:)  !< held at a drive velocity (e fixed)
      logical :: any_prescribed = .false.    !< some node is (else prescribed is all .false. already)
      logical, allocatable :: unknown(:)     !< master(i) == i: the node has an unknown of its own
      !> the nodes without an unknown of their own when the roles were made (node_roles: ghosts and held
      !> nodes; the drive's nodes, held later, keep their values in fill_slaves and are not among them)
      integer, allocatable :: dependent(:)
      real(dp), allocatable :: e(:), du(:), velocity(:), acceleration(:), external(:), residual(:), forces(:)
      real(dp), allocatable :: work(:), reaction(:)
      logical :: external_zero = .false.  !< external is all zero already (a step without external forces)
      !> Newton's right-hand sides (the residual's, the constraint's; the consistent mass's two) and the line
      !> search's starting e
      real(dp), allocatable :: rhs(:, :), start(:)
      ! the drive's point constraint (folded weights over the nodes) and its multiplier
      real(dp), allocatable :: weight(:)
      real(dp) :: target = 0.0_dp, multiplier = 0.0_dp
      real(dp) :: drive_velocity = 0.0_dp  !< the velocity of the driven nodes
      logical :: constrained = .false.
      !> the step has a drive (its held nodes and reaction: without one the reaction stays zero)
      logical :: driven = .false.
      !> the affine law on the hat, lumped mass, dynamic, no mirror ghost and no ghost penalty: the residual
      !> and the tangent are passes over the nodes in closed form (residual_hat, tangent_hat)
      logical :: plain_hat = .false.
      !> residual_hat's sums of squares of the residual, round-off and forces over the unknowns, for
      !> relative_measures (where plain_hat holds: every residual is residual_hat's)
      real(dp) :: squares(3) = 0.0_dp
      ! per particle
      real(dp), allocatable :: x_start(:), dstrain(:), stress(:), stiffness(:), volume(:), strain_magnitude(:)
      !> per node, the size of R's round-off from the increments' own: sum over the stiffness terms of
      !> |K_IJ| |du_J| (times eps); the residual cannot fall below a few eps of it (floor_ulps)
      real(dp), allocatable :: roundoff(:)
      real(dp), allocatable :: modulus(:), yield(:), hardening_modulus(:), hardening(:)
      !> the step's law is affine in the increment (linear): R(e) is formed on the nodes from what the
      !> step's start assembled (affine_start), without a pass over the particles
      logical :: affine = .false.
      !> hencky's law on the hat with FLIP, without the ghost penalty: a cell's particles share their strain
      !> increment, so R(e) is formed per cell from the start's sums, one logarithm a cell (hencky_cells)
      logical :: hencky_cells = .false.
      !> off: every law's residual from the particles (tests compare the forms)
      logical :: node_forms = .true.
      !> the affine law's node-wise sums over the particles, on the nodes 0..elements before folding: the
      !> stiffness S_IJ = sum_p dN_Ip k_p V_p dN_Jp and the sums of its terms' magnitudes, by the offset
      !> d = J - I (band(d, I)); the force shares at sigma_n, sum_p dN_Ip sigma_p^n V_p, and their magnitudes
      real(dp), allocatable :: band(:, :), band_magnitude(:, :), start_force(:), start_magnitude(:)
      !> the hat's: per cell i (nodes i, i + 1), the sums over its particles of dN^2 k_p V_p, of dN sigma_p^n V_p
      !> (dN the left node's gradient) and of its magnitude (affine_start_hat); hencky_cells' at the last
      !> residual (hencky_logarithms): the tangent's sum dN^2 E_p V_p/(1 + d eps), the share sum dN sigma_p V_p
      !> and the sum of its terms' magnitudes. affine_forces_hat and residual_hat form the residual from either.
      real(dp), allocatable :: cells(:, :)
      !> hencky_cells' sums per cell at the step's start (start_pass_hat): sum dN^2 E_p V_p, sum dN sigma_p^n V_p
      !> and its magnitude; the smallest and largest sigma_p^n/E_p of its particles (stress_ranges); the cell's
      !> ln(1 + d eps) at the last residual and whether its stresses there have both signs; 1 per particle
      !> (start_pass_hat's stiffness ratio for hencky's sums)
      real(dp), allocatable :: hencky(:, :), ranges(:, :), logarithms(:), ones(:)
      logical, allocatable :: mixed(:)
      type(banded_t) :: tangent, mass_matrix, mass_factors, mass_magnitude
      type(ghost_knots_t) :: knots
   end type implicit_t

   !> The run's stepper of the implicit integrators: the generic path's shape cache and material (its
   !> start, u_cm and snapshots are the generic path's) and the integrator's state `im`.
   type, extends(generic_stepper_t) :: implicit_stepper_t
      type(implicit_t) :: im
   contains
      procedure :: start => implicit_stepper_start
      procedure :: step => implicit_stepper_step
      procedure :: stop_reason => implicit_stop_reason
      procedure :: report => implicit_stepper_report
      procedure :: sync_state => implicit_sync_state
   end type implicit_stepper_t

contains

   !> Integer id of an integrator name (explicit for anything else; the configuration is validated).
   pure integer function integrator_id(name)
      character(len=*), intent(in) :: name
      integrator_id = max(name_id(name, known_integrators, first=integrator_explicit), integrator_explicit)
   end function integrator_id

   !> The integrator's options from the configuration.
   subroutine implicit_init(im, config)
      type(implicit_t), intent(out) :: im
      class(settings_t), intent(in) :: config
      im%kind = integrator_id(config%integrator)
      im%mass = merge(mass_consistent, mass_lumped, trim(config%mass) == 'consistent')
      im%tolerance = config%newton_tolerance
      im%max_iterations = config%max_newton_iterations
      im%ghost_penalty = config%ghost_penalty
      if (im%ghost_penalty < 0.0_dp) im%ghost_penalty = merge(0.0_dp, automatic_ghost_penalty, trim(config%shape) == 'linear')
      allocate (im%residuals(0:min(im%max_iterations, initial_residuals)))
   end subroutine implicit_init

   !> One step from t to t + dt (implicit) or one load increment to the load factor t + dt (quasi-static):
   !> the step's grid data, Newton, and the particles' update; on failure (im%failed) the particles keep
   !> their state and the run stops.
   subroutine implicit_advance(im, scene, cache, particles, grid, dt, material, t, totals)
      type(implicit_t), intent(inout) :: im
      class(loads_t), intent(in) :: scene
      type(shape_cache_t), intent(inout) :: cache
      type(particles_t), intent(inout) :: particles
      type(grid_t), intent(inout) :: grid
      real(dp), intent(in) :: dt, t
      type(material_t), intent(in) :: material
      type(pass_totals_t), intent(out) :: totals
      call prepare_step(im, scene, cache, particles, grid, dt, material, t, totals)
      if (totals%outside /= 0) return ! the left_grid guard stops the run
      if (im%failed) return ! a singular consistent mass matrix
      call newton_solve(im, cache, particles, grid, material)
      if (im%failed) return
      call update_particles(im, cache, particles, grid, material, totals)
   end subroutine implicit_advance

   !> Everything before Newton: shape functions at the start-of-step positions, P2G, the nodes' roles,
   !> v_n and a_n, f_ext at the step's end, the drive and the ghost knots; e = 0 (du = dt v_n, or 0
   !> quasi-statically).
   subroutine prepare_step(im, scene, cache, particles, grid, dt, material, t, totals)
      type(implicit_t), intent(inout) :: im
      class(loads_t), intent(in) :: scene
      type(shape_cache_t), intent(inout) :: cache
      type(particles_t), intent(in) :: particles
      type(grid_t), intent(inout) :: grid
      real(dp), intent(in) :: dt, t
      type(material_t), intent(in) :: material
      type(pass_totals_t), intent(out) :: totals
      logical :: dynamic, fused
      dynamic = im%kind == integrator_implicit
      im%failed = .false.
      im%singular_mass = .false.
      im%dt = dt
      call locate_particles(cache, grid, particles, totals)
      if (totals%outside /= 0) return
      call choose_forms(im, cache, material)
      ! m, p and (dynamic) f_int(sigma_n); the hat with FLIP with the affine law's cell sums in the same pass
      fused = hat_flip_update(im, cache)
      if (fused) then
         call start_hat(im, cache, particles, grid, material)
      else
         call p2g_mass_momentum(cache, particles, grid, with_force=dynamic)
      end if
      call workspace(im, grid%elements, particles%count)
      call node_roles(im, grid)
      call particle_data(im, cache, particles, material)
      if (im%affine .and. .not. fused) call affine_start(im, cache, particles, material, grid%elements)
      ! (e = 0 in lumped_kinematics' pass where it runs)
      if (.not. (dynamic .and. im%mass == mass_lumped)) im%e = 0.0_dp
      im%multiplier = 0.0_dp
      im%constrained = .false.
      im%driven = scene%drives .and. dynamic
      if (dynamic) then ! (v_n and a_n on every node)
         call start_kinematics(im, scene, cache, particles, grid, t)
      else
         im%velocity = 0.0_dp
         im%acceleration = 0.0_dp
      end if
      ! the external force at the step's end (quasi-statically the load factor t + dt of the loads)
      if (scene%external_forces .and. .not. scene%drives) then
         grid%force = 0.0_dp
         call scene%add_forces(grid, t + dt, cache, particles)
         call mirror_fold(grid, .false., .true.)
         im%external = grid%force
         if (.not. dynamic) im%external = (t + dt)*im%external
         im%external_zero = .false.
      else if (.not. im%external_zero) then ! (cleared once for the steps without external forces)
         im%external = 0.0_dp
         im%external_zero = .true.
      end if
      if (scene%drives .and. dynamic) call drive_constraint(im, scene, cache, particles, grid)
      im%knots%count = 0
      if (im%ghost_penalty > 0.0_dp) call find_ghost_knots(cache, grid, particles%x, im%volume, im%modulus, &
                                                           im%ghost_penalty, im%knots)
      im%plain_hat = (im%affine .or. im%hencky_cells) .and. cache%support == 2 .and. dynamic .and. &
                     im%mass == mass_lumped .and. .not. (grid%mirror .or. grid%mirror_right >= 0) .and. im%knots%count == 0
      ! (cleared where Newton assembles it, before it reads it)
      call banded_init(im%tangent, grid%elements + 1, cache%support - 1 + merge(1, 0, im%ghost_penalty > 0.0_dp), &
                       cleared=.false.)
   end subroutine prepare_step

   !> The residual's form, the same for every step of a run: the affine law's from the nodes, hencky_cells'
   !> from the cells, or else from the particles.
   pure subroutine choose_forms(im, cache, material)
      type(implicit_t), intent(inout) :: im
      type(shape_cache_t), intent(in) :: cache
      type(material_t), intent(in) :: material
      im%affine = im%node_forms .and. material%law == law_linear
      im%hencky_cells = im%node_forms .and. material%law == law_hencky .and. hat_flip_update(im, cache) .and. &
                        .not. im%ghost_penalty > 0.0_dp
   end subroutine choose_forms

   !> The step's arrays, allocated in the run's start (implicit_stepper_start) and again when the grid or
   !> particle count changes.
   subroutine workspace(im, n, count)
      type(implicit_t), intent(inout) :: im
      integer, intent(in) :: n, count
      if (allocated(im%e)) then
         if (size(im%e) == n + 1 .and. size(im%x_start) == count) return
         deallocate (im%master, im%sign, im%prescribed, im%unknown, im%e, im%du, im%velocity, im%acceleration, &
                     im%external, im%residual, im%forces, im%work, im%reaction, im%weight, im%rhs, im%start, &
                     im%x_start, im%dstrain, &
                     im%roundoff, im%strain_magnitude, &
                     im%stress, im%stiffness, im%volume, im%modulus, im%yield, im%hardening_modulus, im%hardening)
      end if
      allocate (im%master(0:n), im%sign(0:n), im%prescribed(0:n), im%unknown(0:n), im%e(0:n), im%du(0:n), &
                im%velocity(0:n), im%acceleration(0:n), im%external(0:n), im%residual(0:n), im%forces(0:n), &
                im%work(0:n), im%reaction(0:n), im%weight(0:n), im%roundoff(0:n), im%rhs(0:n, 2), im%start(0:n))
      ! (every node array written once here, where it is made: its pages' first touch is not a step's)
      im%e = 0.0_dp; im%du = 0.0_dp; im%velocity = 0.0_dp; im%acceleration = 0.0_dp; im%external = 0.0_dp
      im%residual = 0.0_dp; im%forces = 0.0_dp; im%work = 0.0_dp; im%weight = 0.0_dp; im%roundoff = 0.0_dp
      im%rhs = 0.0_dp; im%start = 0.0_dp; im%sign = 1.0_dp; im%master = -1; im%unknown = .false.
      allocate (im%x_start(count), im%dstrain(count), im%stress(count), im%stiffness(count), im%volume(count), &
                im%strain_magnitude(count), &
                im%modulus(count), im%yield(count), im%hardening_modulus(count), im%hardening(count))
      im%reaction = 0.0_dp
      im%prescribed = .false.
      im%any_prescribed = .false.
      im%external_zero = .false.
   end subroutine workspace

   !> Which unknown each node takes: free nodes with mass their own, mirror ghosts their partner's with
   !> the sign -1 (mpm_operations, mirror_fold), fixed and empty nodes none (-1).
   subroutine node_roles(im, grid)
      type(implicit_t), intent(inout) :: im
      type(grid_t), intent(inout) :: grid
      integer :: i, j, k, dependent
      real(dp) :: lightest
      ! (and the lightest node with mass; the nodes with mass take their own unknown in the same pass, the
      ! held nodes and the ghosts lose theirs after it)
      lightest = huge(1.0_dp)
      dependent = 0
      do i = 0, grid%elements
         im%sign(i) = 1.0_dp
         im%unknown(i) = grid%mass(i) > grid%empty_mass
         im%master(i) = merge(i, -1, im%unknown(i))
         if (.not. im%unknown(i)) dependent = dependent + 1
         if (grid%mass(i) > 0.0_dp) lightest = min(lightest, grid%mass(i))
      end do
      grid%min_node_mass = lightest
      if (im%any_prescribed) then ! (a clearing pass only after a step with a drive)
         im%prescribed = .false.
         im%any_prescribed = .false.
      end if
      do k = 1, size(grid%fixed)
         i = grid%fixed(k)
         if (im%unknown(i)) dependent = dependent + 1
         im%unknown(i) = .false.
         im%master(i) = -1
      end do
      if (grid%mirror) then
         do j = 1, grid%ghost
            i = grid%ghost - j
            if (im%unknown(i)) dependent = dependent + 1
            im%unknown(i) = .false.
            im%master(i) = merge(grid%ghost + j, -1, im%master(grid%ghost + j) >= 0)
            im%sign(i) = -1.0_dp
         end do
      end if
      if (grid%mirror_right >= 0) then
         do j = 1, grid%ghost
            i = grid%mirror_right + j
            if (im%unknown(i)) dependent = dependent + 1
            im%unknown(i) = .false.
            im%master(i) = merge(grid%mirror_right - j, -1, im%master(grid%mirror_right - j) >= 0)
            im%sign(i) = -1.0_dp
         end do
      end if
      if (allocated(im%dependent)) then
         if (size(im%dependent) /= dependent) deallocate (im%dependent)
      end if
      if (.not. allocated(im%dependent)) allocate (im%dependent(dependent))
      dependent = 0
      do i = 0, grid%elements
         if (im%unknown(i)) cycle
         dependent = dependent + 1
         im%dependent(dependent) = i
      end do
   end subroutine node_roles

   !> Each particle's material parameters and the law's state at the step's start, its volume V_p^n and its
   !> position x_p^n, as far as the step reads them: the affine law and hencky_cells on the hat without the
   !> ghost penalty read neither the moduli nor the volumes (the start's cell sums form them), the hat's
   !> update with FLIP moves the particles from where they are (update_hat_flip).
   subroutine particle_data(im, cache, particles, material)
      type(implicit_t), intent(inout) :: im
      type(shape_cache_t), intent(in) :: cache
      type(particles_t), intent(in) :: particles
      type(material_t), intent(in) :: material
      if (.not. hat_flip_update(im, cache)) im%x_start = particles%x
      if ((im%affine .or. im%hencky_cells) .and. cache%support == 2 .and. .not. im%ghost_penalty > 0.0_dp) return
      im%modulus = material%youngs_modulus
      if (allocated(particles%youngs_modulus_of)) im%modulus = particles%youngs_modulus_of
      ! the plastic parameters and state: read by the laws without a loop of their own in
      ! law_stress_stiffness only (the elastoplastic one)
      if (material%law /= law_linear .and. material%law /= law_hencky) then
         im%yield = material%yield_stress
         if (allocated(particles%yield_stress_of)) im%yield = particles%yield_stress_of
         im%hardening_modulus = material%hardening_modulus
         if (allocated(particles%hardening_modulus_of)) im%hardening_modulus = particles%hardening_modulus_of
         im%hardening = 0.0_dp
         if (allocated(particles%hardening)) im%hardening = particles%hardening
      end if
      im%volume = particles%volume_ratio*particles%volume0_of
   end subroutine particle_data

   !> The step's update is the hat's with FLIP in one pass (update_hat_flip).
   pure logical function hat_flip_update(im, cache)
      type(implicit_t), intent(in) :: im
      type(shape_cache_t), intent(in) :: cache
      hat_flip_update = im%kind == integrator_implicit .and. cache%kind == shape_linear .and. .not. cache%total .and. &
                        cache%transfer == transfer_flip
   end function hat_flip_update

   !> v_n and a_n (lumped: p/m and f/m; consistent: M v = p, M a = f solved), f = f_ext(t_n) - f_int(sigma_n)
   !> + the drive's reaction at t_n (grid%force holds f_int(sigma_n) from P2G).
   subroutine start_kinematics(im, scene, cache, particles, grid, t)
      type(implicit_t), intent(inout) :: im
      class(loads_t), intent(in) :: scene
      type(shape_cache_t), intent(inout) :: cache
      type(particles_t), intent(in) :: particles
      type(grid_t), intent(inout) :: grid
      real(dp), intent(in) :: t
      integer :: info
      if (scene%external_forces .and. .not. scene%drives) call scene%add_forces(grid, t, cache, particles)
      call mirror_fold(grid, .false., .true.)
      if (im%driven) grid%force = grid%force + im%reaction ! (zero without a drive)
      call nodal_velocities(grid)
      if (im%mass == mass_lumped) then
         call lumped_kinematics(grid%elements, im%unknown, grid%velocity, grid%force, grid%mass, im%velocity, &
                                im%acceleration, im%e)
      else
         call consistent_mass(im, cache, particles, grid)
         if (im%failed) then
            im%velocity = 0.0_dp
            im%acceleration = 0.0_dp
            return
         end if
         im%rhs(:, 1) = merge(grid%momentum, 0.0_dp, im%unknown)
         im%rhs(:, 2) = merge(grid%force, 0.0_dp, im%unknown)
         call banded_solve(im%mass_factors, im%rhs, info)
         im%velocity = im%rhs(:, 1)
         im%acceleration = im%rhs(:, 2)
      end if
      call fill_slaves(im, im%velocity)
      call fill_slaves(im, im%acceleration)
   end subroutine start_kinematics

   !> The lumped mass's v_n = p/m and a_n = f/m on the unknowns, zero on the other nodes (fill_slaves sets the
   !> ghosts'), and Newton's first e = 0.
   pure subroutine lumped_kinematics(n, unknown, grid_velocity, force, mass, velocity, acceleration, e)
      integer, intent(in) :: n
      logical, intent(in) :: unknown(0:n)
      real(dp), intent(in) :: grid_velocity(0:n), force(0:n), mass(0:n)
      real(dp), intent(out) :: velocity(0:n), acceleration(0:n), e(0:n)
      integer :: i
      e = 0.0_dp
      do i = 0, n
         velocity(i) = 0.0_dp
         acceleration(i) = 0.0_dp
         if (unknown(i)) then
            velocity(i) = grid_velocity(i)
            acceleration(i) = force(i)/mass(i)
         end if
      end do
   end subroutine lumped_kinematics

   !> M_IJ = sum_p m_p N_Ip N_Jp folded onto the unknowns (identity rows for the held nodes), and its factors.
   subroutine consistent_mass(im, cache, particles, grid)
      type(implicit_t), intent(inout) :: im
      type(shape_cache_t), intent(in) :: cache
      type(particles_t), intent(in) :: particles
      type(grid_t), intent(in) :: grid
      integer :: p, k, l, a, b, info
      call banded_init(im%mass_matrix, grid%elements + 1, cache%support - 1)
      if (cache%support == 2) then
         call consistent_mass_hat(particles%count, size(cache%weight, 1), grid%elements, cache%first, cache%weight, &
                                  particles%mass_of, im%master, im%sign, im%mass_matrix%ab)
      else
         do p = 1, particles%count
            do k = 1, cache%support
               a = im%master(cache%first(p) + k - 1)
               if (a < 0) cycle
               do l = 1, cache%support
                  b = im%master(cache%first(p) + l - 1)
                  if (b < 0) cycle
                  call banded_add(im%mass_matrix, a + 1, b + 1, im%sign(cache%first(p) + k - 1)* &
                                  im%sign(cache%first(p) + l - 1)*particles%mass_of(p)*cache%weight(p, k)* &
                                  cache%weight(p, l))
               end do
            end do
         end do
      end if
      call hold_rows(im%mass_matrix, im%unknown)
      im%mass_factors = im%mass_matrix
      im%mass_magnitude = im%mass_matrix
      im%mass_magnitude%ab = abs(im%mass_matrix%ab)
      call banded_factor(im%mass_factors, info)
      ! M = sum_p m_p N_p N_p^T has rank at most the particle count: with one particle per element a body
      ! with free ends, or a particle entering a new cell, leaves it singular (a zero pivot: the solves
      ! gave NaN); the run stops naming it (status newton_not_converged, singular_mass)
      if (info > 0) then
         im%failed = .true.
         im%singular_mass = .true.
         im%singular_node = info - 1
         im%iterations = 0
         im%failed_residual = 0.0_dp
      end if
   end subroutine consistent_mass

   !> consistent_mass's sums for the hat (band 1: A(a, b) in ab(3 + a - b, b + 1)), block by block: each
   !> particle's four products m_p N_k N_l (sign_k sign_l m_p N_k N_l where a node is a ghost; none for a
   !> held node) formed in a loop of their own, then added in particle order, as banded_add added the values
   !> consistent_mass formed (a loop that adds each product where it forms it is contracted to fused
   !> multiply-adds where the build has them, another rounding). Where both nodes are unknowns of their own
   !> the sign factors, exactly 1, are left out.
   subroutine consistent_mass_hat(count, rows, n, first, weight, mass, master, sign, ab)
      integer, intent(in) :: count, rows, n
      integer, intent(in) :: first(count), master(0:n)
      real(dp), intent(in) :: weight(rows, 2), mass(count), sign(0:n)
      real(dp), intent(inout) :: ab(4, n + 1)
      integer, parameter :: diagonal = 3
      real(dp) :: products(block_size, 2, 2)
      integer :: b0, m, j, p, i, k, l, a, b
      do b0 = 1, count, block_size
         m = min(block_size, count - b0 + 1)
         do j = 1, m
            p = b0 + j - 1
            i = first(p)
            do k = 1, 2
               do l = 1, 2
                  if (master(i) == i .and. master(i + 1) == i + 1) then
                     products(j, k, l) = mass(p)*weight(p, k)*weight(p, l)
                  else
                     products(j, k, l) = sign(i + k - 1)*sign(i + l - 1)*mass(p)*weight(p, k)*weight(p, l)
                  end if
               end do
            end do
         end do
         do j = 1, m
            p = b0 + j - 1
            i = first(p)
            do k = 1, 2
               a = master(i + k - 1)
               if (a < 0) cycle
               do l = 1, 2
                  b = master(i + l - 1)
                  if (b < 0) cycle
                  ab(diagonal + a - b, b + 1) = ab(diagonal + a - b, b + 1) + products(j, k, l)
               end do
            end do
         end do
      end do
   end subroutine consistent_mass_hat

   !> The scene's drive: its nodes held at the drive velocity (e = dt (V - v_n)/2, so v_{n+1} = V) and its
   !> point constraint sum_k w_k v_{n+1,k} = V, i.e. sum_k w_k e_k = dt (V - sum_k w_k v_n,k)/2, over the
   !> unknowns (weights folded, held nodes' share moved to the target).
   subroutine drive_constraint(im, scene, cache, particles, grid)
      type(implicit_t), intent(inout) :: im
      class(loads_t), intent(in) :: scene
      type(shape_cache_t), intent(in) :: cache
      type(particles_t), intent(in) :: particles
      type(grid_t), intent(in) :: grid
      type(drive_t) :: driven
      integer :: k, i
      call scene%drive(grid, cache, particles, driven)
      do k = 1, size(driven%nodes)
         i = driven%nodes(k)
         if (im%master(i) /= i) cycle ! (empty or held already)
         im%master(i) = -1
         im%unknown(i) = .false.
         im%prescribed(i) = .true.
         im%any_prescribed = .true.
         ! the drive's velocity holds over the whole step (du = V dt: the driven end moves as V t exactly,
         ! where the trapezoidal average of a jump from v_n to V would leave it V dt/2 behind for good)
         im%e(i) = im%dt*(driven%velocity - im%velocity(i))
      end do
      im%drive_velocity = driven%velocity
      im%weight = 0.0_dp
      im%target = 0.0_dp
      do k = 1, size(driven%weight)
         i = driven%first + k - 1
         if (driven%weight(k) == 0.0_dp) cycle
         if (im%master(i) >= 0) then
            im%weight(im%master(i)) = im%weight(im%master(i)) + im%sign(i)*driven%weight(k)
            im%target = im%target + 0.5_dp*im%dt*driven%weight(k)*(driven%velocity - im%velocity(i))
         end if
      end do
      im%constrained = any(im%weight /= 0.0_dp)
   end subroutine drive_constraint

   !> Newton-Raphson on e with a backtracking line search on |R| (max_halvings): assemble R (and, unless
   !> converged, the tangent: in the same pass over the particles at a step's start, where Newton always
   !> needs it; after a line search, whose last residual is the next iteration's, in a pass of its own
   !> only when that residual has not converged), factor, solve, update, until
   !> |R| <= tolerance |forces| or R is within floor_ulps eps of its round-off (floor_ulps), and the
   !> drive's constraint holds. Records the relative residuals, the
   !> solves and the smallest reciprocal condition number; sets im%failed when max_iterations solves do
   !> not converge, the residual is not finite or the tangent is singular.
   subroutine newton_solve(im, cache, particles, grid, material)
      type(implicit_t), intent(inout) :: im
      type(shape_cache_t), intent(in) :: cache
      type(particles_t), intent(in) :: particles
      type(grid_t), intent(in) :: grid
      type(material_t), intent(in) :: material
      real(dp) :: relative, roundoff, norm, gap, correction, pivots, before, step, merit, stiffness, multiplier
      integer :: iteration, info, halving
      logical :: floor, assembled, tangent_ready, fused_factor
      ! the plain hat's tangent formed where it is factored (tangent_factor_hat; the drive's constraint reads
      ! the unfactored diagonal)
      fused_factor = im%plain_hat .and. .not. im%constrained
      im%failed = .false.
      im%singular_node = -1
      im%residuals = 0.0_dp
      assembled = .false.
      do iteration = 0, im%max_iterations
         ! a Newton step's residual (the line search's last) or, with the tangent in the same pass, the first
         tangent_ready = .not. assembled
         ! (the line search's last residual comes with its measures)
         if (.not. assembled) then
            call assemble_residual(im, cache, particles, grid, material, with_tangent=.not. fused_factor)
            call relative_measures(im, relative, roundoff, norm)
         end if
         assembled = .false.
         gap = 0.0_dp
         if (im%constrained) gap = im%target - sum(im%weight*im%e)
         if (iteration > ubound(im%residuals, 1)) call grow_residuals(im, iteration)
         im%residuals(iteration) = relative
         if (.not. ieee_is_finite(relative)) exit
         ! converged: the tolerance met, or the residual within floor_ulps of its round-off (floor_ulps)
         floor = relative <= floor_ulps*epsilon(1.0_dp)*roundoff
         if ((relative <= im%tolerance .or. floor) .and. &
             abs(gap) <= im%tolerance*max(abs(im%target), tiny(1.0_dp))) then
            im%iterations = iteration
            im%steps = im%steps + 1
            im%solves = im%solves + iteration
            im%most_solves = max(im%most_solves, iteration)
            if (relative > im%tolerance) then
               im%floor_steps = im%floor_steps + 1
               im%floor_residual = max(im%floor_residual, relative)
            end if
            return
         end if
         if (iteration == im%max_iterations) exit
         stiffness = 0.0_dp
         if (fused_factor) then
            call tangent_factor_hat(grid%elements, im%cells, im%unknown, 4.0_dp/im%dt**2, grid%mass, im%tangent, info)
         else
            if (.not. tangent_ready) call assemble_tangent(im, cache, particles, grid)
            ! the constraint's gap in force units, for the line search's merit: the tangent's diagonal at the
            ! constraint's nodes, weighted
            if (im%constrained) stiffness = sum(abs(im%weight)*im%tangent%ab(2*im%tangent%bandwidth + 1, :))
            call banded_factor(im%tangent, info)
         end if
         if (info > 0) then
            im%singular_node = info - 1
            exit
         end if
         ! the condition number (banded_rcond: about ten solves) where the smallest pivot relative to the largest
         ! reaches a new low: the first step, and a nearly empty node's row (its pivot is what shrinks)
         if (iteration == 0) then
            pivots = banded_pivot_ratio(im%tangent)
            if (pivots < im%min_pivot_ratio) im%min_rcond = min(im%min_rcond, banded_rcond(im%tangent))
            im%min_pivot_ratio = min(im%min_pivot_ratio, pivots)
         end if
         call newton_direction(im, gap, info, correction)
         ! the full Newton step, halved while it does not reduce |R| (a piecewise linear law, as the
         ! elastoplastic one, can make Newton cycle between loading and unloading at long steps)
         multiplier = im%multiplier
         before = hypot(norm, stiffness*gap)
         step = 1.0_dp
         do halving = 0, max_halvings
            call trial_increment(size(im%e) - 1, halving == 0, im%unknown, step, im%rhs(:, 1), im%start, im%e)
            call fill_slaves(im, im%e)
            im%multiplier = multiplier + step*correction
            call assemble_residual(im, cache, particles, grid, material, with_tangent=.false.)
            assembled = .true.
            call relative_measures(im, relative, roundoff, norm)
            merit = hypot(norm, stiffness*(1.0_dp - step)*gap)
            if (merit <= (1.0_dp - 1.0e-4_dp*step)*before .or. halving == max_halvings) exit
            step = 0.5_dp*step
         end do
         if (halving > 0) im%halvings = im%halvings + halving
      end do
      im%failed = .true.
      im%iterations = iteration
      im%failed_residual = relative
   end subroutine newton_solve

   !> The line search's e = start + step delta on the unknowns (`first`: start = e first, the step's e).
   pure subroutine trial_increment(n, first, unknown, step, delta, start, e)
      integer, intent(in) :: n
      logical, intent(in) :: first, unknown(0:n)
      real(dp), intent(in) :: step, delta(0:n)
      real(dp), intent(inout) :: start(0:n), e(0:n)
      integer :: i
      if (first) then
         do i = 0, n
            start(i) = e(i)
            if (unknown(i)) e(i) = start(i) + step*delta(i)
         end do
      else
         do i = 0, n
            if (unknown(i)) e(i) = start(i) + step*delta(i)
         end do
      end if
   end subroutine trial_increment

   !> The Newton step in im%rhs(:, 1): K delta = -R on the unknowns, with the factored tangent; under the
   !> drive's constraint the bordered system's, delta = y + d(lambda) z (K z = w, w.delta = gap), and
   !> d(lambda) in `correction` (0 without it).
   subroutine newton_direction(im, gap, info, correction)
      type(implicit_t), intent(inout) :: im
      real(dp), intent(in) :: gap
      integer, intent(out) :: info
      real(dp), intent(out) :: correction
      integer :: columns
      columns = merge(2, 1, im%constrained)
      info = 0
      if (im%constrained) then
         im%rhs(:, 1) = merge(-im%residual, 0.0_dp, im%unknown)
         im%rhs(:, 2) = im%weight
         call banded_solve(im%tangent, im%rhs(:, 1:columns), info)
      else
         call banded_solve_negated(im%tangent, im%residual, im%unknown, im%rhs(:, 1))
      end if
      correction = 0.0_dp
      if (im%constrained) then
         correction = (gap - sum(im%weight*im%rhs(:, 1)))/sum(im%weight*im%rhs(:, 2))
         im%rhs(:, 1) = im%rhs(:, 1) + correction*im%rhs(:, 2)
      end if
   end subroutine newton_direction

   !> Room in im%residuals for solve `iteration` (doubled, kept values, the rest 0; at most max_iterations).
   subroutine grow_residuals(im, iteration)
      type(implicit_t), intent(inout) :: im
      integer, intent(in) :: iteration
      real(dp), allocatable :: grown(:)
      integer :: last
      last = ubound(im%residuals, 1)
      allocate (grown(0:int(min(max(2_i8*last, int(iteration, i8)), int(im%max_iterations, i8)))))
      grown = 0.0_dp
      grown(0:last) = im%residuals
      call move_alloc(grown, im%residuals)
   end subroutine grow_residuals

   !> |R| / |forces| (`relative`: 0 when nothing acts; at most 1), |roundoff| / |forces| (`roundoff`, see
   !> floor_ulps) and |R| (`norm`, the line search's), norms over the unknowns, in one pass over the nodes.
   subroutine relative_measures(im, relative, roundoff, norm)
      type(implicit_t), intent(in) :: im
      real(dp), intent(out) :: relative, roundoff, norm
      real(dp) :: residual2, roundoff2, scale2
      if (im%plain_hat) then ! (residual_hat's)
         residual2 = im%squares(1)
         roundoff2 = im%squares(2)
         scale2 = im%squares(3)
      else
         call sums_of_squares(size(im%master) - 1, im%unknown, im%residual, im%roundoff, im%forces, residual2, &
                              roundoff2, scale2)
      end if
      relative = relative_to_forces(im, im%residual, residual2, scale2)
      roundoff = relative_to_forces(im, im%roundoff, roundoff2, scale2)
      norm = sqrt(residual2)
      ! (squares beyond the doubles: the scaled form)
      if (.not. ieee_is_finite(residual2)) norm = norm2(pack(im%residual, im%unknown))
   end subroutine relative_measures

   !> relative_measures' sums of squares over the unknowns of the nodes 0..n.
   pure subroutine sums_of_squares(n, unknown, residual, roundoff, forces, residual2, roundoff2, scale2)
      integer, intent(in) :: n
      logical, intent(in) :: unknown(0:n)
      real(dp), intent(in) :: residual(0:n), roundoff(0:n), forces(0:n)
      real(dp), intent(out) :: residual2, roundoff2, scale2
      integer :: i
      residual2 = 0.0_dp
      roundoff2 = 0.0_dp
      scale2 = 0.0_dp
      do i = 0, n
         if (.not. unknown(i)) cycle
         residual2 = residual2 + residual(i)**2
         roundoff2 = roundoff2 + roundoff(i)**2
         scale2 = scale2 + forces(i)**2
      end do
   end subroutine sums_of_squares

   !> |field| / |forces| from the sums of squares over the unknowns (0 when the field is 0 there).
   real(dp) function relative_to_forces(im, field, size2, scale2) result(relative)
      type(implicit_t), intent(in) :: im
      real(dp), intent(in) :: field(0:), size2, scale2
      real(dp) :: scale
      ! (a NaN field stays NaN, where "> 0" once made it 0: converged)
      relative = 0.0_dp
      if (.not. size2 == 0.0_dp) relative = sqrt(size2)/sqrt(scale2)
      ! squares beyond the doubles (forces above 1e154): the same norms in scaled form (norm2), where an
      ! infinite scale once made every residual 0
      if (.not. ieee_is_finite(scale2) .or. .not. ieee_is_finite(size2)) then
         scale = norm2(pack(im%forces, im%unknown))
         relative = norm2(pack(field, im%unknown))/scale
         ! (an infinite force has no scale: no residual is small against it)
         if (.not. ieee_is_finite(scale)) relative = ieee_value(scale, ieee_quiet_nan)
      end if
   end function relative_to_forces

   !> The residual R(e) on the unknowns (their rows; held nodes' rows hold their reaction), the force
   !> scale |forces| and, `with_tangent`, the tangent dR/de (assemble_tangent).
   subroutine assemble_system(im, cache, particles, grid, material, with_tangent)
      type(implicit_t), intent(inout) :: im
      type(shape_cache_t), intent(in) :: cache
      type(particles_t), intent(in) :: particles
      type(grid_t), intent(in) :: grid
      type(material_t), intent(in) :: material
      logical, intent(in) :: with_tangent
      call assemble_residual(im, cache, particles, grid, material, with_tangent)
   end subroutine assemble_system

   !> R(e) from the particles' stresses at d eps_p = sum_J dN_Jp du_J, du = dt v_n + e (kept in im%dstrain,
   !> im%stress for the tangent and the update), and the force scale; `with_tangent`: the tangent at the
   !> same strains too (assemble_tangent), its particles' part in the same pass over the particles.
   subroutine assemble_residual(im, cache, particles, grid, material, with_tangent)
      type(implicit_t), intent(inout) :: im
      type(shape_cache_t), intent(in) :: cache
      type(particles_t), intent(in) :: particles
      type(grid_t), intent(in) :: grid
      type(material_t), intent(in) :: material
      logical, intent(in) :: with_tangent
      real(dp) :: inertia_factor
      integer :: i, k, n, mixed_cells
      logical :: dynamic
      n = grid%elements
      call fill_slaves(im, im%e)
      if (im%hencky_cells) then
         call hencky_logarithms(n, im%dt, grid%inv_dx, im%velocity, im%e, im%hencky, im%ranges, im%logarithms, &
                                im%mixed, mixed_cells, im%cells)
         if (mixed_cells > 0) call mixed_magnitudes(particles%count, size(cache%gradient, 1), n, cache%first, &
                                                    cache%gradient, particles%stress, particles%volume_ratio, &
                                                    particles%volume0_of, material%youngs_modulus, im%logarithms, &
                                                    im%mixed, im%cells, particles%youngs_modulus_of)
      end if
      if (im%plain_hat) then ! (the tangent, if asked, in finish_tangent: tangent_hat)
         call residual_hat(n, im%dt, im%velocity, im%e, merge(0.0_dp, 1.0_dp, im%hencky_cells), im%cells, grid%mass, &
                           im%acceleration, im%external, im%unknown, im%prescribed, im%constrained, im%multiplier, &
                           im%weight, 4.0_dp/im%dt**2, im%du, im%residual, im%forces, im%roundoff, im%squares)
         if (with_tangent) call finish_tangent(im, grid)
         return
      end if
      if (im%affine .or. im%hencky_cells) then
         ! (the affine forms set every node's sums: nothing to clear)
         call node_increments(n, im%dt, im%velocity, im%e, im%du)
      else
         ! (one loop: the clearing in loops of its own becomes three memset calls)
         do i = 0, n
            im%du(i) = im%dt*im%velocity(i) + im%e(i)
            im%residual(i) = 0.0_dp
            im%forces(i) = 0.0_dp
            im%roundoff(i) = 0.0_dp
         end do
      end if
      if (with_tangent) call banded_zero(im%tangent)
      if (im%affine .or. im%hencky_cells) then
         ! the linear law: the same sums formed on the nodes from the step's start (affine_start); hencky_cells
         ! from its cells' logarithms
         if (cache%support == 2) then
            call affine_forces_hat(n, merge(0.0_dp, 1.0_dp, im%hencky_cells), im%cells, im%du, im%residual, &
                                   im%forces, im%roundoff)
         else
            call affine_forces(n, cache%support - 1, im%band, im%band_magnitude, im%start_force, im%start_magnitude, &
                               im%du, im%residual, im%forces, im%roundoff)
         end if
         if (with_tangent) call fold_stiffness(im, cache%support, n)
      else
         ! the particles' stresses over the increment and their force shares dN_Ip sigma_p V_p^n (and stiffness)
         call particle_strains(im, cache, particles%count, n)
         call law_stress_stiffness(material%law, particles%count, im%modulus, im%yield, im%hardening_modulus, &
                                   im%dstrain, particles%stress, particles%volume_ratio, im%hardening, im%stress, &
                                   im%stiffness)
         call particle_forces(im, cache, particles%count, n, .true., with_tangent)
      end if
      ! folded onto the unknowns (a ghost's share to its partner, reflected; the ghosts are dependent nodes)
      do k = 1, size(im%dependent)
         i = im%dependent(k)
         if (im%master(i) < 0 .or. im%unknown(i)) cycle
         im%residual(im%master(i)) = im%residual(im%master(i)) + im%sign(i)*im%residual(i)
         im%forces(im%master(i)) = im%forces(im%master(i)) + im%forces(i)
         im%roundoff(im%master(i)) = im%roundoff(im%master(i)) + im%roundoff(i)
         im%residual(i) = 0.0_dp
         im%forces(i) = 0.0_dp
         im%roundoff(i) = 0.0_dp
      end do
      ! inertia (dynamic) and external force on the rows that balance forces (the unknowns' and, their
      ! reaction, the driven nodes'), the drive's multiplier, the ghost penalty
      dynamic = im%kind == integrator_implicit
      inertia_factor = 4.0_dp/im%dt**2
      if (dynamic .and. im%mass /= mass_lumped) then
         im%work = banded_multiply(im%mass_matrix, in_mass(inertia_factor*im%e - im%acceleration))
         im%forces = im%forces + banded_multiply(im%mass_magnitude, in_mass(inertia_factor*abs(im%e) + &
                                                                             abs(im%acceleration)))
      end if
      call balance_rows(n, dynamic, dynamic .and. im%mass == mass_lumped, inertia_factor, grid%mass, im%e, &
                        im%acceleration, im%external, im%unknown, im%prescribed, im%constrained, im%multiplier, &
                        im%weight, im%work, im%residual, im%forces)
      call ghost_forces(im, im%du)
      if (with_tangent) call finish_tangent(im, grid)
   contains
      !> The vector with the entries of the nodes outside the consistent mass matrix zero (held nodes;
      !> driven nodes are in it: it was formed before the drive held them).
      pure function in_mass(v) result(w)
         real(dp), intent(in) :: v(0:)
         real(dp) :: w(0:size(v) - 1)
         w = merge(v, 0.0_dp, im%unknown .or. im%prescribed)
      end function in_mass
   end subroutine assemble_residual

   !> du = dt v_n + e on the nodes 0..n.
   pure subroutine node_increments(n, dt, velocity, e, du)
      integer, intent(in) :: n
      real(dp), intent(in) :: dt, velocity(0:n), e(0:n)
      real(dp), intent(out) :: du(0:n)
      du = dt*velocity + e
   end subroutine node_increments

   !> The residual's terms after the particles' (folded) shares, in one pass over the nodes: the inertia
   !> (`dynamic`; `lumped`: m_I (4 e_I/dt^2 - a_I) formed here, else given in `work`) and the external force on
   !> the rows that balance forces (the unknowns' and, their reaction, the driven nodes'), the drive's
   !> multiplier; the inertia's and the external force's magnitudes to |forces|.
   subroutine balance_rows(n, dynamic, lumped, inertia_factor, mass, e, acceleration, external, unknown, prescribed, &
                           constrained, multiplier, weight, work, residual, forces)
      integer, intent(in) :: n
      logical, intent(in) :: dynamic, lumped, constrained
      real(dp), intent(in) :: inertia_factor, mass(0:n), e(0:n), acceleration(0:n), external(0:n), multiplier, &
                              weight(0:n)
      logical, intent(in) :: unknown(0:n), prescribed(0:n)
      real(dp), intent(inout) :: work(0:n), residual(0:n), forces(0:n)
      integer :: i
      do i = 0, n
         if (lumped) then
            work(i) = mass(i)*(inertia_factor*e(i) - acceleration(i))
            forces(i) = forces(i) + mass(i)*(inertia_factor*abs(e(i)) + abs(acceleration(i)))
         end if
         if (unknown(i) .or. prescribed(i)) then
            if (dynamic) residual(i) = residual(i) + work(i)
            residual(i) = residual(i) - external(i)
            forces(i) = forces(i) + abs(external(i))
         end if
         if (constrained) residual(i) = residual(i) - multiplier*weight(i)
      end do
   end subroutine balance_rows

   !> The tangent dR/de = 4 M/dt^2 + sum_p dN_Ip (d sigma_p/d eps) dN_Jp V_p^n + the ghost penalty, folded
   !> onto the unknowns (held nodes: hold_rows), at the strains of the last assemble_residual.
   subroutine assemble_tangent(im, cache, particles, grid)
      type(implicit_t), intent(inout) :: im
      type(shape_cache_t), intent(in) :: cache
      type(particles_t), intent(in) :: particles
      type(grid_t), intent(in) :: grid
      if (im%plain_hat) then ! (tangent_hat: every entry set)
         call finish_tangent(im, grid)
         return
      end if
      call banded_zero(im%tangent)
      if (im%affine .or. im%hencky_cells) then
         call fold_stiffness(im, cache%support, grid%elements)
      else
         call particle_forces(im, cache, particles%count, grid%elements, .false., .true.)
      end if
      call finish_tangent(im, grid)
   end subroutine assemble_tangent

   !> The tangent's terms after the particles': the inertia 4 M/dt^2 (dynamic), the ghost penalty, the
   !> held rows.
   subroutine finish_tangent(im, grid)
      type(implicit_t), intent(inout) :: im
      type(grid_t), intent(in) :: grid
      real(dp) :: inertia_factor
      integer :: k, i, n, diagonal
      n = grid%elements
      if (im%plain_hat) then
         call tangent_hat(n, im%cells, im%unknown, 4.0_dp/im%dt**2, grid%mass, im%tangent%ab)
         return
      end if
      diagonal = 2*im%tangent%bandwidth + 1  ! A(a, b) is ab(diagonal + a - b, b) (mpm_banded)
      associate (ab => im%tangent%ab)
         if (im%kind == integrator_implicit) then
            inertia_factor = 4.0_dp/im%dt**2
            if (im%mass == mass_lumped) then
               call add_lumped_inertia(n, size(ab, 1), ab, diagonal, im%unknown, inertia_factor, grid%mass)
            else
               do i = 0, n
                  if (.not. im%unknown(i)) cycle
                  do k = max(0, i - im%mass_matrix%bandwidth), min(n, i + im%mass_matrix%bandwidth)
                     if (.not. im%unknown(k)) cycle
                     ab(diagonal + i - k, k + 1) = ab(diagonal + i - k, k + 1) + inertia_factor* &
                        im%mass_matrix%ab(2*im%mass_matrix%bandwidth + 1 + i - k, k + 1)
                  end do
               end do
            end if
         end if
      end associate
      call ghost_tangent(im)
      call hold_rows(im%tangent, im%unknown)
   end subroutine finish_tangent

   !> The particles' strain increments d eps_p and their magnitudes at the step's du (strain_pass; the hat's
   !> in a loop of its own, strain_pass_hat).
   subroutine particle_strains(im, cache, count, n)
      type(implicit_t), intent(inout) :: im
      type(shape_cache_t), intent(in) :: cache
      integer, intent(in) :: count, n
      if (cache%support == 2) then
         call strain_pass_hat(count, size(cache%gradient, 1), n, cache%first, cache%gradient, im%du, im%dstrain, &
                              im%strain_magnitude)
      else
         call strain_pass(count, size(cache%gradient, 1), cache%support, n, cache%first, cache%gradient, im%du, &
                          im%dstrain, im%strain_magnitude)
      end if
   end subroutine particle_strains

   !> The linear law's residual on the nodes (docs/theory.md, "The affine residual of the linear law"): its
   !> stress sigma_p = sigma_p^n + k_p d eps_p, k_p = E J_p^n, is affine in the increment, so the particles'
   !> force shares are f_I = sum_p dN_Ip sigma_p^n V_p + sum_J S_IJ du_J with S_IJ = sum_p dN_Ip k_p V_p dN_Jp,
   !> both fixed during the step: formed here once, in a pass over the particles at the step's start (with
   !> the magnitudes' sums that make the force scale and the round-off floor). Any support: im%band
   !> (S by the offset d = J - I, band(d, I)), im%band_magnitude, im%start_force, im%start_magnitude; the
   !> hat: per cell (affine_start_hat), im%cells.
   subroutine affine_start(im, cache, particles, material, n)
      type(implicit_t), intent(inout) :: im
      type(shape_cache_t), intent(in) :: cache
      type(particles_t), intent(in) :: particles
      type(material_t), intent(in) :: material
      integer, intent(in) :: n
      integer :: b
      b = cache%support - 1
      if (b == 1) then
         call cell_room(im%cells, 3, n)
         call affine_start_hat(particles%count, size(cache%gradient, 1), n, cache%first, cache%gradient, &
                               particles%stress, material%youngs_modulus, particles%volume_ratio, &
                               particles%volume0_of, im%cells, particles%youngs_modulus_of)
         return
      end if
      ! (the linear law's d sigma/d eps: law_stress_stiffness's product)
      im%stiffness = im%modulus*particles%volume_ratio
      if (allocated(im%band)) then
         if (size(im%band, 1) /= 2*b + 1 .or. size(im%band, 2) /= n + 1) &
            deallocate (im%band, im%band_magnitude, im%start_force, im%start_magnitude)
      end if
      if (.not. allocated(im%band)) allocate (im%band(-b:b, 0:n), im%band_magnitude(-b:b, 0:n), &
                                              im%start_force(0:n), im%start_magnitude(0:n))
      call affine_start_pass(particles%count, size(cache%gradient, 1), b, n, cache%first, cache%gradient, &
                             particles%stress, im%stiffness, im%volume, im%band, im%band_magnitude, im%start_force, &
                             im%start_magnitude)
   end subroutine affine_start

   !> Room for `rows` sums per cell of the cells 0..n - 1 (allocated when the grid changes).
   subroutine cell_room(cells, rows, n)
      real(dp), allocatable, intent(inout) :: cells(:, :)
      integer, intent(in) :: rows, n
      if (allocated(cells)) then
         if (size(cells, 2) /= n) deallocate (cells)
      end if
      if (.not. allocated(cells)) allocate (cells(rows, 0:n - 1), source=0.0_dp)
   end subroutine cell_room

   !> hencky_cells' arrays for the cells 0..n - 1 and `count` particles (allocated when their sizes change).
   subroutine hencky_room(im, n, count)
      type(implicit_t), intent(inout) :: im
      integer, intent(in) :: n, count
      call cell_room(im%cells, 3, n)
      call cell_room(im%hencky, 3, n)
      call cell_room(im%ranges, 2, n)
      if (allocated(im%logarithms)) then
         if (size(im%logarithms) /= n) deallocate (im%logarithms, im%mixed)
      end if
      if (.not. allocated(im%logarithms)) allocate (im%logarithms(0:n - 1), source=0.0_dp)
      if (.not. allocated(im%mixed)) allocate (im%mixed(0:n - 1), source=.false.)
      if (allocated(im%ones)) then
         if (size(im%ones) /= count) deallocate (im%ones)
      end if
      if (.not. allocated(im%ones)) then
         allocate (im%ones(count))
         im%ones = 1.0_dp
      end if
   end subroutine hencky_room

   !> Per cell the smallest and the largest sigma_p^n/E_p of its particles (none: +huge, -huge), for
   !> hencky_logarithms' test whether the cell's stresses sigma^n + E ln(1 + d eps) have one sign. E_p the
   !> material's or, given, the particle's (`modulus_of`).
   subroutine stress_ranges(count, n, first, stress, modulus, ranges, modulus_of)
      integer, intent(in) :: count, n
      integer, intent(in) :: first(count)
      real(dp), intent(in) :: stress(count), modulus
      real(dp), intent(out) :: ranges(2, 0:n - 1)
      real(dp), intent(in), optional :: modulus_of(count)
      real(dp) :: ratio
      integer :: p, i
      ranges(1, :) = huge(1.0_dp)
      ranges(2, :) = -huge(1.0_dp)
      do p = 1, count
         i = first(p)
         if (present(modulus_of)) then
            ratio = stress(p)/modulus_of(p)
         else
            ratio = stress(p)/modulus
         end if
         ! (comparisons: min and max once gave wrong values in a release build's loop)
         if (ratio < ranges(1, i)) ranges(1, i) = ratio
         if (ratio > ranges(2, i)) ranges(2, i) = ratio
      end do
   end subroutine stress_ranges

   !> The start of a step of the hat with FLIP: p2g_mass_momentum's sums with the force and, for the affine law,
   !> affine_start's, for hencky_cells their cell sums (start_pass_hat).
   subroutine start_hat(im, cache, particles, grid, material)
      type(implicit_t), intent(inout) :: im
      type(shape_cache_t), intent(in) :: cache
      type(particles_t), intent(in) :: particles
      type(grid_t), intent(inout) :: grid
      type(material_t), intent(in) :: material
      integer :: n
      n = grid%elements
      if (im%hencky_cells) then
         call hencky_room(im, n, particles%count)
         call start_pass_hat(particles%count, n, cache%first, cache%weight(:, 2), grid%inv_dx, &
                             particles%mass_of, particles%v, particles%stress, particles%volume_ratio, &
                             particles%volume0_of, grid%mass, grid%momentum, grid%force, material%youngs_modulus, &
                             im%ones, im%hencky, particles%youngs_modulus_of)
         call stress_ranges(particles%count, n, cache%first, particles%stress, material%youngs_modulus, im%ranges, &
                            particles%youngs_modulus_of)
      else if (im%affine) then
         call cell_room(im%cells, 3, n)
         call start_pass_hat(particles%count, n, cache%first, cache%weight(:, 2), grid%inv_dx, &
                             particles%mass_of, particles%v, particles%stress, particles%volume_ratio, &
                             particles%volume0_of, grid%mass, grid%momentum, grid%force, material%youngs_modulus, &
                             particles%volume_ratio, im%cells, particles%youngs_modulus_of)
      else
         call start_pass_hat(particles%count, n, cache%first, cache%weight(:, 2), grid%inv_dx, &
                             particles%mass_of, particles%v, particles%stress, particles%volume_ratio, &
                             particles%volume0_of, grid%mass, grid%momentum, grid%force, material%youngs_modulus)
      end if
      call mirror_fold(grid, .true., .false.)
   end subroutine start_hat

   !> The hat's P2G at a step's start, m_I, p_I and f_I = -sum_p dN_Ip sigma_p V_p (scatter's sums: a cell's
   !> particles next to each other summed in registers, each run added to its nodes; p_p = m_p v_p and
   !> sigma_p V_p formed as scatter forms its columns of them) and, given `cells`, affine_start_hat's sums
   !> (added per particle, as there; a cell's sums held in registers while its particles follow each other),
   !> in one pass over the particles: each value formed by the same operations in the same order (the same
   !> bits). The stiffness k_p = E_p r_p (`ratio`, with `cells`): r = J^n for the linear law (its
   !> d sigma/d eps = E J^n), r = 1 for hencky_cells' sums (hencky's is E/(1 + d eps)). Nothing is
   !> cleared before the pass (a sweep of its own over these arrays): a node or cell beyond the furthest
   !> that a run has reached, in any order of the particles, takes its run's sums (0 + s is s: a run's sums
   !> start from +0 and are never -0), those skipped on the way and those no run reaches are cleared.
   subroutine start_pass_hat(count, n, first, right, inv_dx, mass_of, v, stress, volume_ratio, volume0, &
                             mass, momentum, force, modulus, ratio, cells, modulus_of)
      integer, intent(in) :: count, n
      integer, intent(in) :: first(count)
      !> the shape function of each particle's right node (its left node's is 1 - right, its gradients
      !> -1/dx and 1/dx: linear_shapes' for a particle inside the grid, as every one is here)
      real(dp), intent(in) :: right(count), inv_dx
      real(dp), intent(in) :: mass_of(count), v(count), stress(count), volume_ratio(count), volume0(count), modulus
      real(dp), intent(out) :: mass(0:n), momentum(0:n), force(0:n)
      real(dp), intent(in), optional :: ratio(count)
      real(dp), intent(out), optional :: cells(3, 0:n - 1)
      real(dp), intent(in), optional :: modulus_of(count)
      real(dp) :: mass1, mass2, momentum1, momentum2, force1, force2, q, stress_volume, share, stiffness, volume, &
                  cell1, cell2, cell3, weight1, weight2, gradient1, gradient2
      integer :: p, i, cells_cleared, nodes_cleared
      logical :: run_ends
      gradient1 = -inv_dx
      gradient2 = inv_dx
      cells_cleared = -1 ! the cells 0..cells_cleared and nodes 0..nodes_cleared hold sums (or 0)
      nodes_cleared = -1
      run_ends = .true.
      do p = 1, count
         if (run_ends) then ! a run starts
            mass1 = 0.0_dp; mass2 = 0.0_dp
            momentum1 = 0.0_dp; momentum2 = 0.0_dp
            force1 = 0.0_dp; force2 = 0.0_dp
            if (present(cells)) then
               i = first(p)
               if (i > cells_cleared) then ! (a cell no run has reached: its sums from 0)
                  if (i > cells_cleared + 1) cells(:, cells_cleared + 1:i - 1) = 0.0_dp
                  cells_cleared = i
                  cell1 = 0.0_dp; cell2 = 0.0_dp; cell3 = 0.0_dp
               else
                  cell1 = cells(1, i); cell2 = cells(2, i); cell3 = cells(3, i)
               end if
            end if
         end if
         weight2 = right(p)
         weight1 = 1.0_dp - weight2
         q = mass_of(p)*v(p)
         mass1 = mass1 + weight1*mass_of(p)
         mass2 = mass2 + weight2*mass_of(p)
         momentum1 = momentum1 + weight1*q
         momentum2 = momentum2 + weight2*q
         stress_volume = stress(p)*volume_ratio(p)*volume0(p)
         force1 = force1 - gradient1*stress_volume
         force2 = force2 - gradient2*stress_volume
         i = first(p)
         if (present(cells)) then
            stiffness = modulus*ratio(p)
            if (present(modulus_of)) stiffness = modulus_of(p)*ratio(p)
            volume = volume_ratio(p)*volume0(p)
            share = gradient1*stress(p)*volume
            cell1 = cell1 + gradient1*stiffness*volume*gradient1
            cell2 = cell2 + share
            cell3 = cell3 + abs(share)
         end if
         run_ends = p == count
         if (.not. run_ends) run_ends = first(p + 1) /= i
         if (run_ends) then ! add the run's sums to its nodes
            if (present(cells)) then
               cells(1, i) = cell1; cells(2, i) = cell2; cells(3, i) = cell3
            end if
            ! (a node no run has reached takes the run's sum: 0 + s is s, a run's sum is never -0)
            if (i > nodes_cleared) then
               if (i > nodes_cleared + 1) then
                  mass(nodes_cleared + 1:i - 1) = 0.0_dp
                  momentum(nodes_cleared + 1:i - 1) = 0.0_dp
                  force(nodes_cleared + 1:i - 1) = 0.0_dp
               end if
               mass(i) = mass1
               momentum(i) = momentum1
               force(i) = force1
            else
               mass(i) = mass(i) + mass1
               momentum(i) = momentum(i) + momentum1
               force(i) = force(i) + force1
            end if
            if (i + 1 > nodes_cleared) then
               mass(i + 1) = mass2
               momentum(i + 1) = momentum2
               force(i + 1) = force2
               nodes_cleared = i + 1
            else
               mass(i + 1) = mass(i + 1) + mass2
               momentum(i + 1) = momentum(i + 1) + momentum2
               force(i + 1) = force(i + 1) + force2
            end if
         end if
      end do
      if (present(cells)) cells(:, cells_cleared + 1:n - 1) = 0.0_dp
      mass(nodes_cleared + 1:n) = 0.0_dp
      momentum(nodes_cleared + 1:n) = 0.0_dp
      force(nodes_cleared + 1:n) = 0.0_dp
   end subroutine start_pass_hat

   !> affine_start's sums for any support (`b` = support - 1).
   subroutine affine_start_pass(count, rows, b, n, first, gradient, stress, stiffness, volume, band, band_magnitude, &
                                force, magnitude)
      integer, intent(in) :: count, rows, b, n
      integer, intent(in) :: first(count)
      real(dp), intent(in) :: gradient(rows, b + 1), stress(count), stiffness(count), volume(count)
      real(dp), intent(out) :: band(-b:b, 0:n), band_magnitude(-b:b, 0:n), force(0:n), magnitude(0:n)
      real(dp) :: share, weighted, entry
      integer :: p, k, l, i
      band = 0.0_dp
      band_magnitude = 0.0_dp
      force = 0.0_dp
      magnitude = 0.0_dp
      do p = 1, count
         do k = 1, b + 1
            i = first(p) + k - 1
            share = gradient(p, k)*stress(p)*volume(p)
            force(i) = force(i) + share
            magnitude(i) = magnitude(i) + abs(share)
            weighted = gradient(p, k)*stiffness(p)*volume(p)
            do l = 1, b + 1
               entry = weighted*gradient(p, l)
               band(l - k, i) = band(l - k, i) + entry
               band_magnitude(l - k, i) = band_magnitude(l - k, i) + abs(entry)
            end do
         end do
      end do
   end subroutine affine_start_pass

   !> affine_start's sums for the hat, per cell: its gradients are g = -1/dx and 1/dx (force_pass_hat), so a
   !> particle in cell i gives node i the share g sigma V - c (du_{i+1} - du_i), c = g^2 k V, and node i + 1
   !> that negated; cells(:, i) holds the cell's sums of c, of g sigma^n V and of |g sigma^n V|
   !> (affine_forces_hat forms S du from them; S is the cells' [[C, -C], [-C, C]] summed). The particles'
   !> k = E J^n and V^n = J^n V_0 formed here (particle_data and affine_start's products), E the
   !> material's or, given, the particle's (`modulus_of`).
   subroutine affine_start_hat(count, rows, n, first, gradient, stress, modulus, volume_ratio, volume0, cells, &
                               modulus_of)
      integer, intent(in) :: count, rows, n
      integer, intent(in) :: first(count)
      real(dp), intent(in) :: gradient(rows, 2), stress(count), modulus, volume_ratio(count), volume0(count)
      real(dp), intent(out) :: cells(3, 0:n - 1)
      real(dp), intent(in), optional :: modulus_of(count)
      real(dp) :: share, stiffness, volume
      integer :: p, i
      cells = 0.0_dp
      do p = 1, count
         i = first(p)
         stiffness = modulus*volume_ratio(p)
         if (present(modulus_of)) stiffness = modulus_of(p)*volume_ratio(p)
         volume = volume_ratio(p)*volume0(p)
         share = gradient(p, 1)*stress(p)*volume
         cells(1, i) = cells(1, i) + gradient(p, 1)*stiffness*volume*gradient(p, 1)
         cells(2, i) = cells(2, i) + share
         cells(3, i) = cells(3, i) + abs(share)
      end do
   end subroutine affine_start_hat

   !> The affine law's force shares at du on the nodes 0..n (before folding): residual = f(sigma_n) + S du;
   !> roundoff = |S| |du| (the sum over the particles of |dN_Ip k_p V_p| sum_J |dN_Jp du_J|, as force_pass
   !> forms it); forces = the magnitudes' sum at sigma_n + |S| |du|, which bounds force_pass's sum of
   !> |dN_Ip sigma_p V_p| from above.
   subroutine affine_forces(n, b, band, band_magnitude, force, magnitude, du, residual, forces, roundoff)
      integer, intent(in) :: n, b
      real(dp), intent(in) :: band(-b:b, 0:n), band_magnitude(-b:b, 0:n), force(0:n), magnitude(0:n), du(0:n)
      real(dp), intent(out) :: residual(0:n), forces(0:n), roundoff(0:n)
      real(dp) :: total, spread
      integer :: i, d
      do i = 0, n
         total = 0.0_dp
         spread = 0.0_dp
         do d = max(-b, -i), min(b, n - i)
            total = total + band(d, i)*du(i + d)
            spread = spread + band_magnitude(d, i)*abs(du(i + d))
         end do
         residual(i) = force(i) + total
         roundoff(i) = spread
         forces(i) = magnitude(i) + spread
      end do
   end subroutine affine_forces

   !> affine_forces for the hat from its cells' sums (affine_start_hat): cell i's share of node i is
   !> T_i = F_i - C_i (du_{i+1} - du_i) and of node i + 1 -T_i; its round-off scale C_i (|du_i| + |du_{i+1}|)
   !> (every particle's c >= 0, so the magnitudes' sum is C_i itself) and its force scale |F|_i go to both.
   !> hencky_cells (`affine` 0): the same with the sums of its law at the last hencky_logarithms (cell_shares).
   subroutine affine_forces_hat(n, affine, cells, du, residual, forces, roundoff)
      integer, intent(in) :: n
      real(dp), intent(in) :: affine, cells(3, 0:n - 1), du(0:n)
      real(dp), intent(out) :: residual(0:n), forces(0:n), roundoff(0:n)
      real(dp) :: previous, spread_before, magnitude_before
      integer :: i
      previous = 0.0_dp
      spread_before = 0.0_dp
      magnitude_before = 0.0_dp
      do i = 0, n - 1
         call cell_shares(affine, cells(:, i), du(i), du(i + 1), previous, spread_before, magnitude_before, &
                          residual(i), roundoff(i), forces(i))
      end do
      call last_shares(previous, spread_before, magnitude_before, residual(n), roundoff(n), forces(n))
   end subroutine affine_forces_hat

   !> affine_forces_hat's terms of node i from its cell i (its sums and the increments of its nodes) and from
   !> cell i - 1 (its share, round-off scale and force scale; then cell i's, for node i + 1): the share
   !> F - a C (du_{i+1} - du_i), a = `affine`: 1 for the linear law (1 C is C: the same bits), 0 where F is
   !> the share itself (hencky_logarithms); the round-off scale C (|du_i| + |du_{i+1}|); the force scale
   !> cell(3) + a times the round-off scale (the linear law's bound of the stresses' change; hencky_cells'
   !> cell(3) is the particles' sum itself, force_pass's, which has no round-off term).
   pure subroutine cell_shares(affine, cell, du_left, du_right, previous, spread_before, magnitude_before, residual, &
                               roundoff, forces)
      real(dp), intent(in) :: affine, cell(3), du_left, du_right
      real(dp), intent(inout) :: previous, spread_before, magnitude_before
      real(dp), intent(out) :: residual, roundoff, forces
      real(dp) :: share, spread
      share = cell(2) - (affine*cell(1))*(du_right - du_left)
      spread = cell(1)*(abs(du_left) + abs(du_right))
      residual = share - previous
      roundoff = spread_before + spread
      forces = (magnitude_before + cell(3)) + affine*roundoff
      previous = share
      spread_before = spread
      magnitude_before = cell(3)
   end subroutine cell_shares

   !> ln(1 + x) for |x| <= series_limit by its Taylor series x - x^2/2 + ... + x^9/9, written
   !> x + x^2 t: the remainder is below |x|^10/10, 2^-63/10 of the value at the limit, and x is exact, so
   !> the one rounding that matters is the last sum's (the rest is a few eps of x^2 t, at most 2^-8 of the
   !> value): within 0.51 ulp of the exact value (the library's log is within 1 ulp, log_one_plus's quotient
   !> within 2), without a call or a division. Beyond the limit: mpm_material's log_one_plus. Here, private,
   !> not in mpm_material: gfortran inlines a private function of the same module only, and a call per cell
   !> cost a tenth of a Hencky step.
   elemental real(dp) function log_one_plus_series(x) result(y)
      real(dp), intent(in) :: x
      real(dp) :: t, x2, x4
      ! (Estrin's pairs: the chain of dependent products and sums is 4 deep where Horner's is 9)
      x2 = x*x
      x4 = x2*x2
      t = ((-1.0_dp/2 + x*(1.0_dp/3)) + x2*(-1.0_dp/4 + x*(1.0_dp/5))) + &
          x4*((-1.0_dp/6 + x*(1.0_dp/7)) + x2*(-1.0_dp/8 + x*(1.0_dp/9)))
      y = x + x2*t
   end function log_one_plus_series

   !> log_one_plus_series of each of `x` (for the tests: the scalar function stays private, so that the
   !> compiler writes it into its loop).
   pure function series_logarithms(x) result(y)
      real(dp), intent(in) :: x(:)
      real(dp) :: y(size(x))
      y = log_one_plus_series(x)
   end function series_logarithms

   !> hencky_cells' law at the increments du = dt v_n + e, per cell i (nodes i, i + 1; the hat's gradients
   !> -1/dx and 1/dx, as linear_shapes sets them): d eps formed as strain_pass_hat forms a particle's and
   !> ln(1 + d eps) by its series where |d eps| <= 2^-7 (log_one_plus_series: within half an ulp, without a
   !> call; law_stress_stiffness's form, log_one_plus, beyond), kept in `logarithms`, and from the start's
   !> sums (`hencky`: C = sum dN^2 E V, F, |F|) the cell's sums for cell_shares: the share F + H ln(1 + d eps),
   !> H = sum dN E V = -C dx (the cell's particles' dN = -1/dx: linear_shapes'), the particles' sum of
   !> dN (sigma^n + E ln(1 + d eps)) V; its
   !> force scale, the particles' sum of |dN sigma V|: |share| where their stresses have one sign (the
   !> cell's range of sigma^n/E, `ranges`, all on one side of -ln(1 + d eps)), else 0 and the cell counted
   !> in `mixed_cells` and flagged in `mixed` (mixed_magnitudes adds the particles' terms); the tangent's
   !> C/(1 + d eps) (its round-off scale times |du_i| + |du_{i+1}|: force_pass's sum of
   !> |dN (d sigma/d eps) V| sum_J |dN_J du_J|). A cell without particles (C = 0) takes no logarithm (its
   !> nodes may be empty and their increments anything). A loop of its own: a call (log_one_plus, beyond the
   !> series' limit) clobbers every floating-point register, and in residual_hat's loop would spill its sums.
   pure subroutine hencky_logarithms(n, dt, inv_dx, velocity, e, hencky, ranges, logarithms, mixed, mixed_cells, cells)
      integer, intent(in) :: n
      real(dp), intent(in) :: dt, inv_dx, velocity(0:n), e(0:n), hencky(3, 0:n - 1), ranges(2, 0:n - 1)
      real(dp), intent(out) :: logarithms(0:n - 1), cells(3, 0:n - 1)
      logical, intent(out) :: mixed(0:n - 1)
      integer, intent(out) :: mixed_cells
      real(dp) :: left, right, total, dstrain, u, logarithm, stiffness, share, width
      integer :: i
      width = -1.0_dp/inv_dx
      mixed_cells = 0
      right = dt*velocity(0) + e(0)
      do i = 0, n - 1
         left = right
         right = dt*velocity(i + 1) + e(i + 1)
         ! (from 0 as strain_pass_hat: 0 + (-0) is +0)
         total = 0.0_dp
         total = total + (-inv_dx)*left
         dstrain = total + inv_dx*right
         u = 1.0_dp + dstrain
         logarithm = 0.0_dp
         stiffness = 0.0_dp
         if (hencky(1, i) /= 0.0_dp) then
            if (abs(dstrain) <= series_limit) then
               logarithm = log_one_plus_series(dstrain)
            else
               logarithm = log_one_plus(dstrain)
            end if
            stiffness = hencky(1, i)/u
         end if
         share = hencky(2, i) + (hencky(1, i)*width)*logarithm
         logarithms(i) = logarithm
         cells(1, i) = stiffness
         cells(2, i) = share
         ! the force scale: |share| where the stresses have one sign; else from the particles (mixed_magnitudes)
         mixed(i) = ranges(1, i) + logarithm < 0.0_dp .and. ranges(2, i) + logarithm > 0.0_dp
         cells(3, i) = merge(0.0_dp, abs(share), mixed(i))
         if (mixed(i)) mixed_cells = mixed_cells + 1
      end do
   end subroutine hencky_logarithms

   !> affine_forces_hat's terms of the last node, from its one cell's.
   pure subroutine last_shares(previous, spread_before, magnitude_before, residual, roundoff, forces)
      real(dp), intent(in) :: previous, spread_before, magnitude_before
      real(dp), intent(out) :: residual, roundoff, forces
      residual = -previous
      roundoff = spread_before
      forces = magnitude_before + spread_before
   end subroutine last_shares

   !> assemble_residual where im%plain_hat holds, in one pass over the nodes: du = dt v_n + e
   !> (node_increments), the cells' shares (affine_forces_hat), the inertia, the external force and the
   !> drive's multiplier (balance_rows, lumped) and relative_measures' sums of squares over the unknowns
   !> (sums_of_squares; in `squares`): each value formed by the same operations in the same order (the same
   !> bits). Without mirror ghosts the fold onto the unknowns moves nothing, and without ghost knots the
   !> penalty adds nothing.
   pure subroutine residual_hat(n, dt, velocity, e, affine, cells, mass, acceleration, external, unknown, prescribed, &
                                constrained, multiplier, weight, inertia_factor, du, residual, forces, roundoff, squares)
      integer, intent(in) :: n
      real(dp), intent(in) :: dt, velocity(0:n), e(0:n), affine, cells(3, 0:n - 1), mass(0:n), acceleration(0:n), &
                              external(0:n), multiplier, weight(0:n), inertia_factor
      logical, intent(in) :: unknown(0:n), prescribed(0:n), constrained
      real(dp), intent(out) :: du(0:n), residual(0:n), forces(0:n), roundoff(0:n), squares(3)
      real(dp) :: previous, spread_before, magnitude_before, work, residual2, roundoff2, scale2
      integer :: i
      previous = 0.0_dp
      spread_before = 0.0_dp
      magnitude_before = 0.0_dp
      residual2 = 0.0_dp
      roundoff2 = 0.0_dp
      scale2 = 0.0_dp
      du(0) = dt*velocity(0) + e(0)
      do i = 0, n
         if (i < n) then
            du(i + 1) = dt*velocity(i + 1) + e(i + 1)
            call cell_shares(affine, cells(:, i), du(i), du(i + 1), previous, spread_before, magnitude_before, &
                             residual(i), roundoff(i), forces(i))
         else
            call last_shares(previous, spread_before, magnitude_before, residual(n), roundoff(n), forces(n))
         end if
         work = mass(i)*(inertia_factor*e(i) - acceleration(i))
         forces(i) = forces(i) + mass(i)*(inertia_factor*abs(e(i)) + abs(acceleration(i)))
         if (unknown(i) .or. prescribed(i)) then
            residual(i) = residual(i) + work
            residual(i) = residual(i) - external(i)
            forces(i) = forces(i) + abs(external(i))
         end if
         if (constrained) residual(i) = residual(i) - multiplier*weight(i)
         if (unknown(i)) then
            residual2 = residual2 + residual(i)**2
            roundoff2 = roundoff2 + roundoff(i)**2
            scale2 = scale2 + forces(i)**2
         end if
      end do
      squares = [residual2, roundoff2, scale2]
   end subroutine residual_hat

   !> The tangent where im%plain_hat holds, every entry of the band ab (bandwidth 1) set in one pass over the
   !> nodes: the cells' stiffness (fold_cells_hat: a node's diagonal takes C of each of its cells, the
   !> cell's off-diagonal entries -C where both its nodes are unknowns), the lumped inertia
   !> (add_lumped_inertia), then the held rows (hold_band_rows); each entry the sum the zeroed band and
   !> those loops form, in the same order (the same bits).
   pure subroutine tangent_hat(n, cells, unknown, inertia_factor, mass, ab)
      integer, intent(in) :: n
      real(dp), intent(in) :: cells(3, 0:n - 1), inertia_factor, mass(0:n)
      logical, intent(in) :: unknown(0:n)
      real(dp), intent(out) :: ab(4, n + 1)
      real(dp) :: diagonal, largest
      integer :: i
      largest = 0.0_dp
      do i = 0, n
         ab(1, i + 1) = 0.0_dp
         ab(2, i + 1) = 0.0_dp ! A(i - 1, i)
         ab(4, i + 1) = 0.0_dp ! A(i + 1, i)
         if (i < n) then
            if (unknown(i) .and. unknown(i + 1)) ab(4, i + 1) = 0.0_dp - cells(1, i)
         end if
         if (i > 0) then
            if (unknown(i - 1) .and. unknown(i)) ab(2, i + 1) = 0.0_dp - cells(1, i - 1)
         end if
         diagonal = 0.0_dp
         if (unknown(i)) then
            if (i > 0) diagonal = diagonal + cells(1, i - 1)
            if (i < n) diagonal = diagonal + cells(1, i)
            diagonal = diagonal + inertia_factor*mass(i)
            largest = max(largest, abs(diagonal))
         end if
         ab(3, i + 1) = diagonal
      end do
      if (largest == 0.0_dp) largest = 1.0_dp
      do i = 0, n
         if (.not. unknown(i)) ab(3, i + 1) = ab(3, i + 1) + largest
      end do
   end subroutine tangent_hat

   !> The tangent where im%plain_hat holds and its LU factors in one pass over the nodes: tangent_hat's
   !> entries, each factored as it is formed by banded_factor's operations in its order (the same bits: the
   !> factors, the pivots, the 1-norm and the smallest and largest pivot). A held row's diagonal, the
   !> largest of the unknowns' diagonals, is known only at the end; the factorisation needs none of it
   !> before then (its row and column are zero off the diagonal, so its multiplier is 0 and the next
   !> pivot is that row's own diagonal), and it is written with the pivots' extremes after the pass.
   !> Where a column would need a row interchange or has a zero or non-finite pivot, the two steps
   !> instead (tangent_hat, banded_factor).
   subroutine tangent_factor_hat(n, cells, unknown, inertia_factor, mass, a, info)
      integer, intent(in) :: n
      real(dp), intent(in) :: cells(3, 0:n - 1), inertia_factor, mass(0:n)
      logical, intent(in) :: unknown(0:n)
      type(banded_t), intent(inout) :: a
      integer, intent(out) :: info
      real(dp) :: norm1, smallest, largest, held_diagonal
      logical :: fused, held
      info = 0
      call factor_rows_hat(n, cells, unknown, inertia_factor, mass, a%ab, a%pivots, norm1, smallest, largest, &
                           held_diagonal, held, fused)
      if (.not. fused) then
         call tangent_hat(n, cells, unknown, inertia_factor, mass, a%ab)
         call banded_factor(a, info)
         return
      end if
      if (held) then
         norm1 = max(norm1, held_diagonal)
         if (held_diagonal < smallest) smallest = held_diagonal
         if (held_diagonal > largest) largest = held_diagonal
      end if
      a%norm1 = norm1
      a%interchanged = .false.
      a%smallest_pivot = smallest
      a%largest_pivot = largest
      a%factored = .true.
   end subroutine tangent_factor_hat

   !> tangent_factor_hat's pass on the band as an explicit-shape array (as mpm_banded's factor_rows).
   !> `fused` false: a column needs what the general factorisation does (the band is then to be formed
   !> again).
   pure subroutine factor_rows_hat(n, cells, unknown, inertia_factor, mass, ab, pivots, norm1, smallest, largest, &
                                   held_diagonal, held, fused)
      integer, intent(in) :: n
      real(dp), intent(in) :: cells(3, 0:n - 1), inertia_factor, mass(0:n)
      logical, intent(in) :: unknown(0:n)
      real(dp), intent(out) :: ab(4, n + 1), norm1, smallest, largest, held_diagonal
      integer, intent(out) :: pivots(n + 1)
      logical, intent(out) :: held, fused
      real(dp) :: diagonal, upper, lower, pivot, l
      integer :: i
      norm1 = 0.0_dp
      smallest = huge(1.0_dp)
      largest = 0.0_dp
      held_diagonal = 0.0_dp ! (the largest |diagonal| of the unknowns: tangent_hat's `largest`)
      held = .false.
      fused = .false.
      upper = 0.0_dp ! A(i - 1, i)
      l = 0.0_dp     ! the multiplier of the column before
      do i = 0, n
         lower = 0.0_dp ! A(i + 1, i)
         if (i < n) then
            if (unknown(i) .and. unknown(i + 1)) lower = 0.0_dp - cells(1, i)
         end if
         ab(1, i + 1) = 0.0_dp
         ab(2, i + 1) = upper
         pivots(i + 1) = i + 1
         if (unknown(i)) then
            diagonal = 0.0_dp
            if (i > 0) diagonal = diagonal + cells(1, i - 1)
            if (i < n) diagonal = diagonal + cells(1, i)
            diagonal = diagonal + inertia_factor*mass(i)
            held_diagonal = max(held_diagonal, abs(diagonal))
            norm1 = max(norm1, abs(upper) + abs(diagonal) + abs(lower))
            pivot = diagonal
            if (upper /= 0.0_dp) pivot = pivot - l*upper
            if (.not. abs(pivot) <= huge(1.0_dp) .or. pivot == 0.0_dp) return
            if (i < n) then
               if (.not. abs(lower) <= abs(pivot)) return
            end if
            if (abs(pivot) < smallest) smallest = abs(pivot)
            if (abs(pivot) > largest) largest = abs(pivot)
            ab(3, i + 1) = pivot
            l = 0.0_dp
            if (i < n) l = lower/pivot
            ab(4, i + 1) = l
         else ! (its diagonal after the pass; its multiplier 0/diagonal)
            held = .true.
            l = 0.0_dp
            ab(4, i + 1) = 0.0_dp
         end if
         upper = lower
      end do
      if (held_diagonal == 0.0_dp) held_diagonal = 1.0_dp
      if (.not. held_diagonal <= huge(1.0_dp)) return
      do i = 0, n
         if (.not. unknown(i)) ab(3, i + 1) = 0.0_dp + held_diagonal
      end do
      fused = .true.
   end subroutine factor_rows_hat

   !> The affine law's stiffness S folded onto the unknowns of the tangent (a ghost's row and column its
   !> partner's, with its sign; held nodes none): fold_cells_hat, fold_band.
   subroutine fold_stiffness(im, support, n)
      type(implicit_t), intent(inout) :: im
      integer, intent(in) :: support, n
      if (support == 2) then
         call fold_cells_hat(n, im%cells, im%master, im%sign, size(im%tangent%ab, 1), im%tangent%ab, &
                             2*im%tangent%bandwidth + 1)
      else
         call fold_band(n, ubound(im%band, 1), im%band, im%master, im%sign, size(im%tangent%ab, 1), im%tangent%ab, &
                        2*im%tangent%bandwidth + 1)
      end if
   end subroutine fold_stiffness

   !> S (by offsets, band(d, I) = S(I, I + d)) added to the band ab (A(a, b) in ab(diagonal + a - b, b + 1)).
   subroutine fold_band(n, b, band, master, sign, band_rows, ab, diagonal)
      integer, intent(in) :: n, b, band_rows, diagonal
      integer, intent(in) :: master(0:n)
      real(dp), intent(in) :: band(-b:b, 0:n), sign(0:n)
      real(dp), intent(inout) :: ab(band_rows, n + 1)
      integer :: i, d, a, c
      do i = 0, n
         a = master(i)
         if (a < 0) cycle
         do d = max(-b, -i), min(b, n - i)
            c = master(i + d)
            if (c < 0) cycle
            ab(diagonal + a - c, c + 1) = ab(diagonal + a - c, c + 1) + sign(i)*sign(i + d)*band(d, i)
         end do
      end do
   end subroutine fold_band

   !> The hat's cells' stiffness [[C_i, -C_i], [-C_i, C_i]] on the nodes i, i + 1 added to the band ab (as
   !> fold_band; where both nodes are unknowns of their own, directly).
   subroutine fold_cells_hat(n, cells, master, sign, band_rows, ab, diagonal)
      integer, intent(in) :: n, band_rows, diagonal
      integer, intent(in) :: master(0:n)
      real(dp), intent(in) :: cells(3, 0:n - 1), sign(0:n)
      real(dp), intent(inout) :: ab(band_rows, n + 1)
      real(dp) :: c
      integer :: i, k, l, a, b
      do i = 0, n - 1
         c = cells(1, i)
         if (master(i) == i .and. master(i + 1) == i + 1) then
            call add_hat_block(band_rows, n, ab, diagonal, i, c)
            cycle
         end if
         do k = 0, 1
            a = master(i + k)
            if (a < 0) cycle
            do l = 0, 1
               b = master(i + l)
               if (b < 0) cycle
               ab(diagonal + a - b, b + 1) = ab(diagonal + a - b, b + 1) + sign(i + k)*sign(i + l)*merge(c, -c, k == l)
            end do
         end do
      end do
   end subroutine fold_cells_hat

   !> The lumped inertia 4 m_I/dt^2 on the unknowns' diagonal of the band ab (explicit-shape, as hold_band_rows).
   pure subroutine add_lumped_inertia(n, band_rows, ab, diagonal, unknown, inertia_factor, mass)
      integer, intent(in) :: n, band_rows, diagonal
      real(dp), intent(inout) :: ab(band_rows, n + 1)
      logical, intent(in) :: unknown(0:n)
      real(dp), intent(in) :: inertia_factor, mass(0:n)
      integer :: i
      do i = 0, n
         if (unknown(i)) ab(diagonal, i + 1) = ab(diagonal, i + 1) + inertia_factor*mass(i)
      end do
   end subroutine add_lumped_inertia

   !> The particles' strain increments d eps_p = sum_J dN_Jp du_J and their magnitudes sum_J |dN_Jp du_J|.
   !> The particle loops here and in force_pass take explicit-shape arrays: gfortran then indexes them
   !> without the strides of assumed shapes (im's components through their descriptors cost three times the
   !> arithmetic). `rows`: the leading dimension of the shape cache's arrays.
   subroutine strain_pass(count, rows, support, n, first, gradient, du, dstrain, magnitude)
      integer, intent(in) :: count, rows, support, n
      integer, intent(in) :: first(count)
      real(dp), intent(in) :: gradient(rows, support), du(0:n)
      real(dp), intent(out) :: dstrain(count), magnitude(count)
      real(dp) :: share
      integer :: p, k
      dstrain = 0.0_dp
      magnitude = 0.0_dp
      do k = 1, support
         do p = 1, count
            share = gradient(p, k)*du(first(p) + k - 1)
            dstrain(p) = dstrain(p) + share
            magnitude(p) = magnitude(p) + abs(share)
         end do
      end do
   end subroutine strain_pass

   !> The particles' force shares and stiffness (force_pass; the hat's support of two nodes in a loop of its
   !> own, force_pass_hat).
   subroutine particle_forces(im, cache, count, n, residual_part, tangent_part)
      type(implicit_t), intent(inout) :: im
      type(shape_cache_t), intent(in) :: cache
      integer, intent(in) :: count, n
      logical, intent(in) :: residual_part, tangent_part
      if (cache%support == 2 .and. residual_part) then
         call force_pass_hat(count, size(cache%gradient, 1), n, cache%first, cache%gradient, im%stress, im%stiffness, &
                             im%volume, im%strain_magnitude, im%master, im%sign, tangent_part, im%residual, im%forces, &
                             im%roundoff, size(im%tangent%ab, 1), im%tangent%ab, 2*im%tangent%bandwidth + 1)
      else
         call force_pass(count, size(cache%gradient, 1), cache%support, n, cache%first, cache%gradient, im%stress, &
                         im%stiffness, im%volume, im%strain_magnitude, im%master, im%sign, residual_part, tangent_part, &
                         im%residual, im%forces, im%roundoff, size(im%tangent%ab, 1), im%tangent%ab, &
                         2*im%tangent%bandwidth + 1)
      end if
   end subroutine particle_forces

   !> strain_pass for the hat (support 2): each particle's two terms written out, summed as the loop does.
   subroutine strain_pass_hat(count, rows, n, first, gradient, du, dstrain, magnitude)
      integer, intent(in) :: count, rows, n
      integer, intent(in) :: first(count)
      real(dp), intent(in) :: gradient(rows, 2), du(0:n)
      real(dp), intent(out) :: dstrain(count), magnitude(count)
      real(dp) :: left, right, total, spread
      integer :: p
      do p = 1, count
         left = gradient(p, 1)*du(first(p))
         right = gradient(p, 2)*du(first(p) + 1)
         ! (from 0 as the loop: 0 + (-0) is +0)
         total = 0.0_dp
         spread = 0.0_dp
         total = total + left
         spread = spread + abs(left)
         dstrain(p) = total + right
         magnitude(p) = spread + abs(right)
      end do
   end subroutine strain_pass_hat

   !> force_pass (residual part, tangent part when `tangent_part`) for the hat: each particle's two nodes
   !> written out. Where both are unknowns of their own (sign +1) the tangent's four entries are added
   !> directly, each the value of the product force_pass forms (its sign factors are exactly 1); a particle
   !> at a held node or a ghost takes force_pass's loop. The same values added in the same order: the same
   !> bits.
   subroutine force_pass_hat(count, rows, n, first, gradient, stress, stiffness, volume, magnitude, master, sign, &
                             tangent_part, residual, forces, roundoff, band_rows, ab, diagonal)
      integer, intent(in) :: count, rows, n, band_rows, diagonal
      integer, intent(in) :: first(count), master(0:n)
      real(dp), intent(in) :: gradient(rows, 2), stress(count), stiffness(count), volume(count), magnitude(count), &
                              sign(0:n)
      logical, intent(in) :: tangent_part
      real(dp), intent(inout) :: residual(0:n), forces(0:n), roundoff(0:n), ab(band_rows, n + 1)
      real(dp) :: left, left_stiffness, rounding, tangent_share, share
      integer :: p, i, k, l, node, a, b
      ! The hat's gradients are -1/dx and 1/dx (times the particle's inside flag, mpm_shape_linear):
      ! gradient(p, 2) = -gradient(p, 1) exactly, so each product of the right node is the left one's
      ! negated (exact), and the tangent's four entries are one product and its negation.
      do p = 1, count
         i = first(p)
         left = gradient(p, 1)*stress(p)*volume(p)
         left_stiffness = gradient(p, 1)*stiffness(p)*volume(p)
         rounding = abs(left_stiffness)*magnitude(p)
         residual(i) = residual(i) + left
         forces(i) = forces(i) + abs(left)
         roundoff(i) = roundoff(i) + rounding
         residual(i + 1) = residual(i + 1) - left
         forces(i + 1) = forces(i + 1) + abs(left)
         roundoff(i + 1) = roundoff(i + 1) + rounding
         if (.not. tangent_part) cycle
         if (master(i) == i .and. master(i + 1) == i + 1) then
            tangent_share = left_stiffness*gradient(p, 1)
            call add_hat_block(band_rows, n, ab, diagonal, i, tangent_share)
            cycle
         end if
         do k = 1, 2
            node = i + k - 1
            a = master(node)
            if (a < 0) cycle
            share = sign(node)*gradient(p, k)*stiffness(p)*volume(p)
            do l = 1, 2
               b = master(i + l - 1)
               if (b < 0) cycle
               ab(diagonal + a - b, b + 1) = ab(diagonal + a - b, b + 1) + share*sign(i + l - 1)*gradient(p, l)
            end do
         end do
      end do
   end subroutine force_pass_hat

   !> The hat's stiffness block [[c, -c], [-c, c]] on the nodes i, i + 1, both unknowns of their own, added to
   !> the band ab (A(a, b) in ab(diagonal + a - b, b + 1)).
   pure subroutine add_hat_block(band_rows, n, ab, diagonal, i, c)
      integer, intent(in) :: band_rows, n, diagonal, i
      real(dp), intent(inout) :: ab(band_rows, n + 1)
      real(dp), intent(in) :: c
      ab(diagonal, i + 1) = ab(diagonal, i + 1) + c
      ab(diagonal - 1, i + 2) = ab(diagonal - 1, i + 2) - c
      ab(diagonal + 1, i + 1) = ab(diagonal + 1, i + 1) - c
      ab(diagonal, i + 2) = ab(diagonal, i + 2) + c
   end subroutine add_hat_block

   !> One pass over the particles: `residual_part`, the force shares dN_Ip sigma_p V_p^n to R and |forces|,
   !> and the round-off scale |dN_Ip k_p V_p^n| sum_J |dN_Jp du_J| to roundoff; `tangent_part`, the
   !> stiffness dN_Ip k_p V_p^n dN_Jp to the band ab (A(a, b) in ab(diagonal + a - b, b + 1)) on the nodes'
   !> unknowns (master: held nodes none, a ghost its partner's with its sign). Each sum runs in the order of
   !> the separate loops it replaced (over the particles, then the support): the same bits.
   subroutine force_pass(count, rows, support, n, first, gradient, stress, stiffness, volume, magnitude, master, sign, &
                         residual_part, tangent_part, residual, forces, roundoff, band_rows, ab, diagonal)
      integer, intent(in) :: count, rows, support, n, band_rows, diagonal
      integer, intent(in) :: first(count), master(0:n)
      real(dp), intent(in) :: gradient(rows, support), stress(count), stiffness(count), volume(count), &
                              magnitude(count), sign(0:n)
      logical, intent(in) :: residual_part, tangent_part
      real(dp), intent(inout) :: residual(0:n), forces(0:n), roundoff(0:n), ab(band_rows, n + 1)
      real(dp) :: share
      integer :: p, k, l, node, a, b
      do p = 1, count
         if (residual_part) then
            do k = 1, support
               node = first(p) + k - 1
               share = gradient(p, k)*stress(p)*volume(p)
               residual(node) = residual(node) + share
               forces(node) = forces(node) + abs(share)
               roundoff(node) = roundoff(node) + abs(gradient(p, k)*stiffness(p)*volume(p))*magnitude(p)
            end do
         end if
         if (tangent_part) then
            do k = 1, support
               node = first(p) + k - 1
               a = master(node)
               if (a < 0) cycle
               share = sign(node)*gradient(p, k)*stiffness(p)*volume(p)
               do l = 1, support
                  b = master(first(p) + l - 1)
                  if (b < 0) cycle
                  ab(diagonal + a - b, b + 1) = ab(diagonal + a - b, b + 1) + share*sign(first(p) + l - 1)*gradient(p, l)
               end do
            end do
         end if
      end do
   end subroutine force_pass

   !> The rows of the nodes without an unknown of their own (held, or a mirror ghost) get the diagonal
   !> entry of the unknowns' largest, and nothing else (their right-hand side is zero): the matrix stays
   !> nonsingular and its condition number is that of the unknowns' block, not of a scale mismatch.
   subroutine hold_rows(a, unknown)
      type(banded_t), intent(inout) :: a
      logical, intent(in) :: unknown(0:)
      call hold_band_rows(size(unknown) - 1, size(a%ab, 1), a%ab, 2*a%bandwidth + 1, unknown)
   end subroutine hold_rows

   !> hold_rows on the band as an explicit-shape array (nodes 0..n; the diagonal in row `diagonal`).
   pure subroutine hold_band_rows(n, band_rows, ab, diagonal, unknown)
      integer, intent(in) :: n, band_rows, diagonal
      real(dp), intent(inout) :: ab(band_rows, n + 1)
      logical, intent(in) :: unknown(0:n)
      real(dp) :: largest
      integer :: i
      largest = 0.0_dp
      do i = 0, n
         if (unknown(i)) largest = max(largest, abs(ab(diagonal, i + 1)))
      end do
      if (largest == 0.0_dp) largest = 1.0_dp
      do i = 0, n
         if (.not. unknown(i)) ab(diagonal, i + 1) = ab(diagonal, i + 1) + largest
      end do
   end subroutine hold_band_rows

   !> The ghost penalty's forces K_g du on the unknowns (du: the step's increment), folded as the rest.
   subroutine ghost_forces(im, du)
      type(implicit_t), intent(inout) :: im
      real(dp), intent(in) :: du(0:)
      integer :: g, j, node, width
      real(dp) :: jump
      width = size(im%knots%stencil)
      do g = 1, im%knots%count
         associate (s => im%knots%start(g))
            jump = sum(im%knots%stencil*du(s:s + width - 1))
            do j = 1, width
               node = s + j - 1
               if (im%master(node) < 0) cycle
               im%residual(im%master(node)) = im%residual(im%master(node)) + &
                                              im%sign(node)*im%knots%stiffness(g)*im%knots%stencil(j)*jump
               im%forces(im%master(node)) = im%forces(im%master(node)) + &
                                            abs(im%knots%stiffness(g)*im%knots%stencil(j)*jump)
               im%roundoff(im%master(node)) = im%roundoff(im%master(node)) + abs(im%knots%stiffness(g)* &
                  im%knots%stencil(j))*sum(abs(im%knots%stencil*du(s:s + width - 1)))
            end do
         end associate
      end do
   end subroutine ghost_forces

   !> The ghost penalty's stiffness (gamma E/dx) d d^T, folded onto the unknowns.
   subroutine ghost_tangent(im)
      type(implicit_t), intent(inout) :: im
      integer :: g, j, k, a, b, width
      width = size(im%knots%stencil)
      do g = 1, im%knots%count
         associate (s => im%knots%start(g))
            do j = 1, width
               a = im%master(s + j - 1)
               if (a < 0) cycle
               do k = 1, width
                  b = im%master(s + k - 1)
                  if (b < 0) cycle
                  call banded_add(im%tangent, a + 1, b + 1, im%sign(s + j - 1)*im%sign(s + k - 1)* &
                                  im%knots%stiffness(g)*im%knots%stencil(j)*im%knots%stencil(k))
               end do
            end do
         end associate
      end do
   end subroutine ghost_tangent

   !> A ghost takes its partner's value reflected; held nodes that are not driven keep 0 (the nodes of
   !> im%dependent: every other node keeps its value).
   subroutine fill_slaves(im, field)
      type(implicit_t), intent(in) :: im
      real(dp), intent(inout) :: field(0:)
      integer :: k, i
      do k = 1, size(im%dependent)
         i = im%dependent(k)
         if (im%master(i) >= 0 .and. im%master(i) /= i) then
            field(i) = im%sign(i)*field(im%master(i))
         else if (im%master(i) < 0 .and. .not. im%prescribed(i)) then
            field(i) = 0.0_dp
         end if
      end do
   end subroutine fill_slaves

   !> The particles from the converged grid solution: v_{n+1} by the run's transfer (mpm_operations, g2p,
   !> with grid velocity v_{n+1} and acceleration (v_{n+1} - v_n)/dt), x_p = x_p^n + sum_I N_Ip du_I, the
   !> law's state by d eps_p; the drive's reaction kept for the next step's a_n; the totals of the step.
   subroutine update_particles(im, cache, particles, grid, material, totals)
      type(implicit_t), intent(inout) :: im
      type(shape_cache_t), intent(inout) :: cache
      type(particles_t), intent(inout) :: particles
      type(grid_t), intent(inout) :: grid
      type(material_t), intent(in) :: material
      type(pass_totals_t), intent(inout) :: totals
      integer :: outside
      logical :: hat_flip, linear
      outside = totals%outside
      ! the hat with FLIP: G2P and the move in one pass (update_hat_flip), with the linear law's update
      hat_flip = hat_flip_update(im, cache)
      linear = hat_flip .and. im%affine .and. im%kind == integrator_implicit
      if (im%kind == integrator_implicit) then
         call end_kinematics(grid%elements, im%dt, im%velocity, im%e, grid%velocity, grid%acceleration)
         if (im%driven) then
            where (im%prescribed) ! driven at V over the whole step (drive_constraint)
               grid%velocity = im%drive_velocity
               grid%acceleration = (im%drive_velocity - im%velocity)/im%dt
            end where
         end if
         if (hat_flip) then
            call update_hat_flip(particles%count, grid%elements, cache%first, cache%weight(:, 2), &
                                 im%affine .or. im%hencky_cells, im%dstrain, &
                                 grid%acceleration, im%du, im%dt, particles%x0, particles%mass_of, &
                                 grid%origin, grid%origin + grid%length, grid%inv_dx, particles%x, particles%v, &
                                 totals%kinetic_energy, totals%displacement, totals%max_cell_move, totals%furthest, &
                                 outside, linear, material%youngs_modulus, particles%volume0_of, particles%stress, &
                                 particles%volume_ratio, totals%strain_energy, totals%min_volume_ratio, &
                                 particles%youngs_modulus_of)
            totals%outside = outside
         else
            call g2p(cache, particles, grid, im%dt, totals)
         end if
         if (im%driven) im%reaction = merge(im%residual, 0.0_dp, im%prescribed)
         if (im%constrained) im%reaction = im%reaction + im%multiplier*im%weight
      else
         grid%velocity = 0.0_dp
         totals%kinetic_energy = 0.0_dp
      end if
      if (.not. hat_flip) then
         totals%outside = outside
         call move_particles(particles%count, size(cache%weight, 1), cache%support, grid%elements, cache%first, &
                             cache%weight, im%du, im%x_start, particles%x0, particles%mass_of, grid%origin, &
                             grid%origin + grid%length, grid%inv_dx, particles%x, totals%displacement, &
                             totals%max_cell_move, totals%furthest, totals%outside)
      end if
      ! (the affine law's residual formed no strains: the converged ones here, or in update_hat_flip)
      if (im%affine .and. .not. hat_flip) call particle_strains(im, cache, particles%count, grid%elements)
      if (linear) then ! (update_hat_flip's)
         totals%plastic_work = 0.0_dp
      else if (im%hencky_cells) then
         call hencky_update(particles%count, grid%elements, cache%first, im%dstrain, material%youngs_modulus, &
                            im%logarithms, particles%volume0_of, particles%stress, particles%volume_ratio, &
                            totals%strain_energy, particles%youngs_modulus_of)
         totals%min_volume_ratio = minval(particles%volume_ratio)
         totals%plastic_work = 0.0_dp
      else
         call update_material_finite(material, im%dstrain, particles, totals%strain_energy, totals%min_volume_ratio, &
                                     totals%plastic_work, im%stress)
      end if
   end subroutine update_particles

   !> hencky_cells' force scale of the cells whose particles' stresses have both signs (`mixed`): the sum of
   !> their |dN sigma_p V_p|, sigma_p = sigma_p^n + E_p ln(1 + d eps) (as hencky_update forms it), V_p = J^n V_0
   !> (force_pass's terms), added to cells(3, :) (0 there). Every particle is inside the grid (a step with one
   !> outside stops before Newton).
   subroutine mixed_magnitudes(count, rows, n, first, gradient, stress_n, volume_ratio, volume0, modulus, logarithms, &
                               mixed, cells, modulus_of)
      integer, intent(in) :: count, rows, n
      integer, intent(in) :: first(count)
      real(dp), intent(in) :: gradient(rows, 2), stress_n(count), volume_ratio(count), volume0(count), modulus, &
                              logarithms(0:n - 1)
      logical, intent(in) :: mixed(0:n - 1)
      real(dp), intent(inout) :: cells(3, 0:n - 1)
      real(dp), intent(in), optional :: modulus_of(count)
      real(dp) :: stiffness
      integer :: p, i
      do p = 1, count
         i = first(p)
         if (.not. mixed(i)) cycle
         stiffness = modulus
         if (present(modulus_of)) stiffness = modulus_of(p)
         cells(3, i) = cells(3, i) + abs(gradient(p, 1)*(stress_n(p) + stiffness*logarithms(i))* &
                                         (volume_ratio(p)*volume0(p)))
      end do
   end subroutine mixed_magnitudes

   !> hencky_cells' law state at the converged increments, update_material_finite's for hencky in one pass:
   !> sigma_p = sigma_p^n + E_p ln(1 + d eps) with the cell's logarithm of the last residual,
   !> J_p <- J_p (1 + d eps_p), and the stored energy, stored_energy's sum of sigma^2 J V_0/(2 E) in its
   !> order (the same bits). E_p the material's or, given, the particle's (`modulus_of`). (Here rather than
   !> in mpm_material: its logarithm is the cell's, and a call of the law per particle across modules is not
   !> inlined.)
   subroutine hencky_update(count, n, first, dstrain, modulus, logarithms, volume0, stress, volume_ratio, energy, &
                            modulus_of)
      integer, intent(in) :: count, n
      integer, intent(in) :: first(count)
      real(dp), intent(in) :: dstrain(count), modulus, logarithms(0:n - 1), volume0(count)
      real(dp), intent(inout) :: stress(count), volume_ratio(count)
      real(dp), intent(out) :: energy
      real(dp), intent(in), optional :: modulus_of(count)
      real(dp) :: stiffness
      integer :: p
      energy = 0.0_dp
      do p = 1, count
         stiffness = modulus
         if (present(modulus_of)) stiffness = modulus_of(p)
         stress(p) = stress(p) + stiffness*logarithms(first(p))
         volume_ratio(p) = volume_ratio(p)*(1.0_dp + dstrain(p))
         energy = energy + 0.5_dp*stress(p)*stress(p)*(volume_ratio(p)*volume0(p))/stiffness
      end do
   end subroutine hencky_update

   !> The grid's v_{n+1} = v_n + 2 e/dt and a = 2 e/dt^2 (for G2P: (v_{n+1} - v_n)/dt) on the nodes 0..n.
   pure subroutine end_kinematics(n, dt, velocity, e, grid_velocity, grid_acceleration)
      integer, intent(in) :: n
      real(dp), intent(in) :: dt, velocity(0:n), e(0:n)
      real(dp), intent(out) :: grid_velocity(0:n), grid_acceleration(0:n)
      integer :: i
      do i = 0, n
         grid_velocity(i) = velocity(i) + 2.0_dp*e(i)/dt
         grid_acceleration(i) = 2.0_dp*e(i)/dt**2
      end do
   end subroutine end_kinematics

   !> The particles' update of the hat with FLIP in one pass, block by block: G2P's v_p += dt sum_I N_Ip a_I
   !> and the kinetic energy (g2p: its gather, gather2_plain, and gather_move's velocity update and lanes),
   !> and the move with its totals (move_particles); each value formed by the same operations in the same
   !> order as there (the same bits). The products N_Ip du_I of the move are formed in a loop of their own
   !> and summed in another, as move_particles' array expression: a build with fused multiply-add does not
   !> contract the sum (another rounding).
   subroutine update_hat_flip(count, n, first, right, strains, dstrain, acceleration, du, dt, &
                              x0, mass, lo, hi, inv_dx, x, v, kinetic_energy, displacement, max_cell_move, &
                              furthest, outside, linear, modulus, volume0, stress, volume_ratio, energy, smallest, &
                              modulus_of)
      integer, intent(in) :: count, n
      integer, intent(in) :: first(count)
      !> the shape function of each particle's right node (as start_pass_hat)
      real(dp), intent(in) :: right(count)
      real(dp), intent(in) :: acceleration(0:n), du(0:n), dt, x0(count), mass(count), lo, hi, inv_dx
      !> `strains`: the strain increments d eps_p too (as strain_pass_hat forms them; in `dstrain` unless
      !> `linear` uses them, block by block)
      logical, intent(in) :: strains
      real(dp), intent(inout) :: dstrain(count)
      real(dp), intent(inout) :: x(count), v(count)
      real(dp), intent(out) :: kinetic_energy, displacement, max_cell_move
      integer, intent(out) :: furthest
      integer, intent(inout) :: outside
      !> `linear` (with `strains`): the linear law's update of each block's particles by their d eps_p
      !> (linear_update_on, linear_update_each_on given `modulus_of`), whose stored energy and smallest J are
      !> update_material_finite's (the same sums in the same order)
      logical, intent(in) :: linear
      real(dp), intent(in) :: modulus, volume0(count)
      real(dp), intent(inout) :: stress(count), volume_ratio(count)
      real(dp), intent(out) :: energy, smallest
      real(dp), intent(in), optional :: modulus_of(count)
      real(dp) :: kinetic(lanes), kinetic_block(block_size), products(block_size, 2), strain_block(block_size), na, &
                  move, total, weight1, weight2, gradient1, gradient2
      integer :: b0, b1, m, i, p, node
      gradient1 = -inv_dx
      gradient2 = inv_dx
      energy = 0.0_dp
      smallest = huge(1.0_dp)
      kinetic = 0.0_dp
      displacement = 0.0_dp
      max_cell_move = 0.0_dp
      furthest = 0
      do b0 = 1, count, block_size
         m = min(block_size, count - b0 + 1)
         do i = 1, m
            p = b0 + i - 1
            node = first(p)
            weight2 = right(p)
            weight1 = 1.0_dp - weight2
            na = weight1*acceleration(node)
            na = na + weight2*acceleration(node + 1)
            v(p) = v(p) + dt*na
            kinetic_block(i) = 0.5_dp*mass(p)*v(p)*v(p)
            products(i, 1) = weight1*du(node)
            products(i, 2) = weight2*du(node + 1)
         end do
         if (strains) then
            do i = 1, m
               p = b0 + i - 1
               node = first(p)
               ! (from 0 as strain_pass_hat: 0 + (-0) is +0)
               total = 0.0_dp
               total = total + gradient1*du(node)
               strain_block(i) = total + gradient2*du(node + 1)
            end do
            b1 = b0 + m - 1
            if (linear) then
               if (present(modulus_of)) then
                  call linear_update_each_on(modulus_of(b0:b1), strain_block(1:m), volume0(b0:b1), stress(b0:b1), &
                                             volume_ratio(b0:b1), energy, smallest)
               else
                  call linear_update_on(modulus, strain_block(1:m), volume0(b0:b1), stress(b0:b1), &
                                        volume_ratio(b0:b1), energy, smallest)
               end if
            else
               dstrain(b0:b1) = strain_block(1:m)
            end if
         end if
         call add_lanes(m, kinetic_block, kinetic)
         ! (move_particles' per-particle lines, written out again: as one procedure that both loops call,
         ! inlined, a build with fused multiply-add contracted move_particles' sums otherwise, another
         ! rounding of the generic shapes' positions)
         do i = 1, m
            p = b0 + i - 1
            move = 0.0_dp
            move = move + products(i, 1)
            move = move + products(i, 2)
            x(p) = x(p) + move ! (from x_p^n: the step moves the particles here only)
            displacement = displacement + mass(p)*(x(p) - x0(p))
            if (abs(move)*inv_dx > max_cell_move) then
               max_cell_move = abs(move)*inv_dx
               furthest = p
            end if
            if (outside == 0 .and. .not. (x(p) >= lo .and. x(p) <= hi)) outside = p
         end do
      end do
      kinetic_energy = lane_total(kinetic)
   end subroutine update_hat_flip

   !> x_p = x_p^n + sum_I N_Ip du_I, and the step's totals of
   !> the positions: the mass-weighted displacement from x0, the largest move in cells and its particle,
   !> the first particle outside [lo, hi] (kept when one is set already). Explicit-shape arrays, as
   !> strain_pass.
   subroutine move_particles(count, rows, support, n, first, weight, du, x_start, x0, mass, lo, hi, inv_dx, x, &
                             displacement, max_cell_move, furthest, outside)
      integer, intent(in) :: count, rows, support, n
      integer, intent(in) :: first(count)
      real(dp), intent(in) :: weight(rows, support), du(0:n), x_start(count), x0(count), mass(count), lo, hi, inv_dx
      real(dp), intent(inout) :: x(count)
      real(dp), intent(out) :: displacement, max_cell_move
      integer, intent(out) :: furthest
      integer, intent(inout) :: outside
      real(dp) :: move
      integer :: p
      displacement = 0.0_dp
      max_cell_move = 0.0_dp
      furthest = 0
      do p = 1, count
         ! (sum of the products, as the array expression the step summed before: a loop of multiply-adds
         ! is contracted to fused ones where the build has them, another rounding)
         move = sum(weight(p, :)*du(first(p):first(p) + support - 1))
         x(p) = x_start(p) + move
         displacement = displacement + mass(p)*(x(p) - x0(p))
         if (abs(move)*inv_dx > max_cell_move) then
            max_cell_move = abs(move)*inv_dx
            furthest = p
         end if
         if (outside == 0 .and. .not. (x(p) >= lo .and. x(p) <= hi)) outside = p
      end do
   end subroutine move_particles

   !> What the integrator adds to /summary: the mean and largest number of linear solves per step, the
   !> smallest reciprocal condition number of the tangent met (mpm_banded's 1-norm estimate, first iteration of
   !> the steps whose smallest pivot ratio was a new low) and the smallest pivot ratio |U_jj|/max |U_ii|,
   !> and the steps accepted at the residual's round-off floor with the largest residual so accepted.
   subroutine implicit_report(im, names, values)
      type(implicit_t), intent(in) :: im
      character(len=32), allocatable, intent(out) :: names(:)
      real(dp), allocatable, intent(out) :: values(:)
      names = [character(len=32) :: 'newton_iterations', 'newton_iterations_max', 'tangent_rcond_min', &
               'tangent_pivot_ratio_min', 'newton_floor_steps', 'newton_floor_residual', 'newton_halvings']
      values = [real(im%solves, dp)/max(im%steps, 1), real(im%most_solves, dp), &
                merge(im%min_rcond, 1.0_dp, im%min_rcond < huge(1.0_dp)), &
                merge(im%min_pivot_ratio, 1.0_dp, im%min_pivot_ratio < huge(1.0_dp)), real(im%floor_steps, dp), &
                im%floor_residual, real(im%halvings, dp)]
   end subroutine implicit_report

   !> The generic start (the particles' energies at t = 0) and, in the run's set-up rather than in its first
   !> step, the arrays the steps write before they read: the shape cache (at the particles' positions), the
   !> step's workspace, the hat's cell sums and the tangent's band, each allocated and written once here
   !> (their pages' first touch, as much as two steps' time at 1e5 particles, is set-up as the explicit
   !> path's is). The particle arrays of the residual's other forms are left to the steps that use them.
   subroutine implicit_stepper_start(self, loads, particles, grid, totals)
      class(implicit_stepper_t), intent(inout) :: self
      class(loads_t), intent(in) :: loads
      type(particles_t), intent(inout) :: particles
      type(grid_t), intent(inout) :: grid
      type(pass_totals_t), intent(out) :: totals
      type(pass_totals_t) :: located
      integer :: n
      call self%generic_stepper_t%start(loads, particles, grid, totals)
      n = grid%elements
      associate (im => self%im, cache => self%cache)
         call locate_particles(cache, grid, particles, located)
         call choose_forms(im, cache, self%material)
         call workspace(im, n, particles%count)
         if (.not. (im%affine .and. hat_flip_update(im, cache))) im%dstrain = 0.0_dp
         if (.not. hat_flip_update(im, cache)) im%x_start = 0.0_dp
         if (im%hencky_cells) then
            call hencky_room(im, n, particles%count)
         else if (im%affine .and. hat_flip_update(im, cache)) then
            call cell_room(im%cells, 3, n)
         end if
         call banded_init(im%tangent, n + 1, cache%support - 1 + merge(1, 0, im%ghost_penalty > 0.0_dp))
         if (im%mass == mass_consistent .and. im%kind == integrator_implicit) then ! (as consistent_mass makes them)
            call banded_init(im%mass_matrix, n + 1, cache%support - 1)
            im%mass_factors = im%mass_matrix
            im%mass_magnitude = im%mass_matrix
         end if
      end associate
   end subroutine implicit_stepper_start

   subroutine implicit_stepper_step(self, loads, particles, grid, dt, t, totals)
      class(implicit_stepper_t), intent(inout) :: self
      class(loads_t), intent(in) :: loads
      type(particles_t), intent(inout) :: particles
      type(grid_t), intent(inout) :: grid
      real(dp), intent(in) :: dt, t
      type(pass_totals_t), intent(out) :: totals
      call implicit_advance(self%im, loads, self%cache, particles, grid, dt, self%material, t, totals)
   end subroutine implicit_stepper_step

   !> A step whose Newton iteration failed: its residual, its solves, and the node of a singular matrix's
   !> zero pivot (the tangent's, or the consistent mass matrix's).
   pure function implicit_stop_reason(self) result(reason)
      class(implicit_stepper_t), intent(in) :: self
      type(stepper_stop_t) :: reason
      reason = stepper_stop_t(stopped=self%im%failed, residual=self%im%failed_residual, iteration=self%im%iterations, &
                              node=self%im%singular_node, mass_matrix=self%im%singular_mass)
   end function implicit_stop_reason

   subroutine implicit_stepper_report(self, names, values)
      class(implicit_stepper_t), intent(in) :: self
      character(len=32), allocatable, intent(out) :: names(:)
      real(dp), allocatable, intent(out) :: values(:)
      call implicit_report(self%im, names, values)
   end subroutine implicit_stepper_report

   !> What the implicit integrator carries from one step to the next, to or from a checkpoint's `state`
   !> (after the generic stepper's): its Newton statistics over the run and the drive's reaction of the
   !> last step (the next step's a_n); every other array is made again at the start of each step.
   subroutine implicit_sync_state(self, state)
      class(implicit_stepper_t), intent(inout) :: self
      type(state_t), intent(inout) :: state
      real(dp), allocatable :: reaction(:)
      integer :: count
      call generic_sync_state(self, state)
      associate (im => self%im)
         call state%sync('implicit.steps', im%steps)
         call state%sync('implicit.solves', im%solves)
         call state%sync('implicit.most_solves', im%most_solves)
         call state%sync('implicit.min_rcond', im%min_rcond)
         call state%sync('implicit.min_pivot_ratio', im%min_pivot_ratio)
         call state%sync('implicit.floor_steps', im%floor_steps)
         call state%sync('implicit.halvings', im%halvings)
         call state%sync('implicit.floor_residual', im%floor_residual)
         if (.not. allocated(im%reaction) .and. state%saving) return ! (not started: no workspace yet)
         if (.not. state%saving .and. .not. state%has('implicit.reaction')) return
         count = 0
         if (state%saving) count = size(im%x_start)
         call state%sync('implicit.particles', count)
         if (state%saving) reaction = im%reaction
         call state%sync('implicit.reaction', reaction)
         if (state%saving .or. .not. allocated(reaction) .or. count <= 0) return
         call workspace(im, ubound(reaction, 1), count) ! (the step's arrays, as the start made them)
         im%reaction = reaction
      end associate
   end subroutine implicit_sync_state
end module mpm_implicit
