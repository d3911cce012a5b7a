!> The implicit integrators (mpm_implicit) against independent expectations, at sizes that take seconds:
!> - the tangent of every shape against central finite differences of the residual at a deformed state
!>   (moved particles, stressed and yielded, mirror ghosts, the ghost penalty, both mass matrices);
!> - the linear law's residual formed on the nodes from the step's start (affine in the increment) against
!>   the particles' residual at the same e, and whole runs of both forms, to round-off (every shape, both
!>   masses, the ghost penalty, mirror ghosts, the drive's constraint, quasi-static); Hencky's residual on the
!>   hat formed per cell (one logarithm a cell) against the particles' likewise (both masses, the drive);
!>   that logarithm's series for small increments against the quadruple-precision logarithm;
!> - Newton: a law linear in the increment converges in one linear solve at newton_tolerance 1e-12 even at
!>   a strain of 1e-8 (the round-off floor of a stress formed from J - 1); the Hencky column converges
!>   quadratically (each relative residual at most a modest constant times the square of the one before);
!> - Newmark's trapezoidal rule: second order in dt (self-convergence on a fixed mesh), runs at 4 and 8
!>   times the explicit limit complete, the consistent mass conserves the linear bar's energy to
!>   round-off and the lumped mass never gains energy (it loses (v_{n+1} - v_n)^T (M_L - M_C) (...)/2);
!> - the static column: with one particle per cell at the cell centres and linear shapes, each particle's
!>   displacement error is exactly (rho g/E) dx^2/8 (the nodal values are exact, a parabola's chord
!>   misses it by that at mid-cell); cpGIMP converges at second order at 30 % strain in 10 load steps for
!>   the linear, Hencky and elastoplastic laws against their closed forms (mpm_scene_column);
!> - the Newton guard's status and message, the namelist's refusals and echo, and the ghost penalty's
!>   effect on the tangent's condition at a cut cell.
program test_implicit
   use mpm_kinds, only: dp
   use mpm_errors, only: error_t
   use mpm_strings, only: str
   use mpm_config, only: config_t, resolve_config, read_config_text, config_namelist, material_of, new_config
   use mpm_simulation, only: run_result_t, guard_message
   use mpm_diagnostics, only: status_ok, status_newton, status_name
   use mpm_pass_totals, only: pass_totals_t
   use mpm_scene, only: scene_t
   use mpm_scene_column, only: column_input_t
   use mpm_grid, only: grid_t, grid_init
   use mpm_particles, only: particles_t, per_particle_data
   use mpm_shape, only: shape_cache_t, shape_id, shape_extra_cells, transfer_id
   use mpm_material, only: material_t, material_state
   use, intrinsic :: iso_fortran_env, only: real128
   use mpm_implicit, only: implicit_t, implicit_init, implicit_advance, prepare_step, assemble_system, newton_solve, &
                           series_logarithms, series_limit, tangent_hat, tangent_factor_hat
   use mpm_banded, only: banded_t, banded_init, banded_factor
   use mpm_testing, only: tester_t, tester
   use mpm_testing_runs, only: run_resolved, set_values, set_value
   implicit none
   type(tester_t) :: t
   character(len=8), parameter :: shapes(5) = [character(len=8) :: 'linear', 'ugimp', 'cpgimp', 'bspline2', 'bspline3']

   t = tester('test_implicit')
   if (t%case('tangent_against_differences')) call tangent_against_differences()
   if (t%case('one_solve_for_a_linear_law')) call one_solve_for_a_linear_law()
   if (t%case('affine_residual')) call affine_residual()
   if (t%case('hencky_cells_residual')) call hencky_cells_residual()
   if (t%case('logarithm_series')) call logarithm_series()
   if (t%case('fused_tangent_factor')) call fused_tangent_factor()
   if (t%case('quadratic_convergence')) call quadratic_convergence()
   if (t%case('temporal_order')) call temporal_order()
   if (t%case('beyond_the_explicit_limit')) call beyond_the_explicit_limit()
   if (t%case('energy')) call energy()
   if (t%case('static_column')) call static_column()
   if (t%case('drives')) call drives()
   if (t%case('newton_guard')) call newton_guard()
   if (t%case('namelist')) call namelist()
   if (t%case('ghost_penalty_conditioning')) call ghost_penalty_conditioning()
   call t%finish()

contains

   !> A run's pieces as run_simulation sets them up (scene, particles, material state, grid with the
   !> shape's extra cells and the scene's margins), for tests that drive the integrator step by step.
   subroutine setup(config, scene, particles, grid, cache, material)
      type(config_t), intent(inout) :: config
      class(scene_t), allocatable, intent(out) :: scene
      type(particles_t), intent(out) :: particles
      type(grid_t), intent(out) :: grid
      type(shape_cache_t), intent(out) :: cache
      type(material_t), intent(out) :: material
      type(error_t), allocatable :: error
      integer :: extra
      call resolve_config(config)
      material = material_of(config)
      call config%scene%make(config, scene, error)
      if (allocated(error)) error stop 'test_implicit: scene'
      cache%kind = shape_id(config%shape)
      cache%transfer = transfer_id(config%transfer)
      call scene%place_particles(config, particles, error)
      call per_particle_data(particles, error)
      call material_state(material, particles, error)
      extra = shape_extra_cells(cache%kind)
      call grid_init(grid, config%elements, config%length, particles%mass, error, &
                     margin=scene%margin_cells(config%dx, config%margin_cells) + extra, fixed=scene%fixed_nodes(), &
                     element_shares=.false., ghost=extra + scene%left_margin_cells(config%dx, config%margin_cells))
      if (allocated(error)) error stop 'test_implicit: grid'
   end subroutine setup

   !> dR/de assembled against (R(e + h u_j) - R(e - h u_j))/(2h) for every unknown j, at e off the converged
   !> solution by a random 1 % of the step's increment, after `steps` steps: every shape on the bar (Hencky,
   !> large strain, ghost penalty on; lumped and consistent mass; and the linear law) and on the
   !> quasi-static column (elastoplastic, yielded; mirror ghosts at its fixed end).
   subroutine tangent_against_differences()
      type(config_t) :: config
      integer :: s
      do s = 1, size(shapes)
         config = new_config()
         config%integrator = 'implicit'
         config%shape = shapes(s)
         config%elements = 16
         config%particles_per_element = 2
         call set_values(config, ['scene.velocity_amplitude=60.0'])      ! strain amplitude v0/c ~ 1 %
         config%dt_fraction = 2.0_dp
         config%ghost_penalty = 0.1_dp
         call check_tangent(config, 12, 'bar hencky '//trim(shapes(s)))
         config%mass = 'consistent'
         call check_tangent(config, 12, 'bar hencky consistent mass '//trim(shapes(s)))
         config%mass = 'lumped'
         config%law = 'linear'
         call check_tangent(config, 12, 'bar linear '//trim(shapes(s)))
         config = new_config()
         config%integrator = 'quasi_static'
         call set_values(config, ["scene.kind='column'"])
         config%shape = shapes(s)
         config%elements = 12
         config%particles_per_element = 2
         call set_values(config, ['scene.length=1.0'])
         call set_values(config, ['scene.youngs_modulus=1.0e10'])
         call set_values(config, ['scene.density=1000.0'])
         call set_values(config, ['scene.gravity=3.0e6'])                ! strain 0.3 at the fixed end
         config%law = 'elastoplastic'
         call set_values(config, ['material.yield_stress=1.0e9'])
         call set_values(config, ['material.hardening_modulus=2.0e9'])
         config%load_steps = 8
         config%max_cell_move = 100.0_dp
         call check_tangent(config, 5, 'column elastoplastic '//trim(shapes(s)))
      end do
   end subroutine tangent_against_differences

   subroutine check_tangent(config, steps, label)
      type(config_t), intent(inout) :: config
      integer, intent(in) :: steps
      character(len=*), intent(in) :: label
      class(scene_t), allocatable :: scene
      type(particles_t) :: particles
      type(grid_t) :: grid
      type(shape_cache_t) :: cache
      type(material_t) :: material
      type(implicit_t) :: im
      type(pass_totals_t) :: totals
      real(dp), allocatable :: e(:), plus(:), minus(:), noise(:)
      real(dp) :: h, worst, scale, exact, difference
      integer :: n, i, j, b, unknowns
      call setup(config, scene, particles, grid, cache, material)
      call implicit_init(im, config)
      do n = 1, steps
         call implicit_advance(im, scene, cache, particles, grid, config%dt, material, (n - 1)*config%dt, totals)
      end do
      call t%check(label//': steps before the check converge', .not. im%failed)
      call prepare_step(im, scene, cache, particles, grid, config%dt, material, steps*config%dt, totals)
      call newton_solve(im, cache, particles, grid, material)
      allocate (noise(0:grid%elements), e(0:grid%elements))
      call random_number(noise)
      e = im%e + 0.01_dp*(noise - 0.5_dp)*maxval(abs(im%du))
      where (.not. im%unknown) e = im%e
      h = 1.0e-6_dp*maxval(abs(im%du))
      b = im%tangent%bandwidth
      worst = 0.0_dp
      unknowns = count(im%unknown)
      do j = 0, grid%elements
         if (.not. im%unknown(j)) cycle
         im%e = e
         im%e(j) = e(j) + h
         call assemble_system(im, cache, particles, grid, material, with_tangent=.false.)
         plus = im%residual
         im%e(j) = e(j) - h
         call assemble_system(im, cache, particles, grid, material, with_tangent=.false.)
         minus = im%residual
         im%e = e
         call assemble_system(im, cache, particles, grid, material, with_tangent=.true.)
         scale = maxval(abs((plus - minus)/(2*h)))
         do i = max(0, j - b), min(grid%elements, j + b)
            if (.not. im%unknown(i)) cycle
            exact = im%tangent%ab(2*b + 1 + i - j, j + 1)
            difference = (plus(i) - minus(i))/(2*h)
            worst = max(worst, abs(exact - difference)/scale)
         end do
      end do
      call t%check(label//': tangent = finite differences of the residual ('//str(unknowns)//' unknowns)', &
                   worst < 1.0e-6_dp .and. unknowns > 5, 'largest relative difference '//str(worst))
   end subroutine check_tangent

   !> The linear law's residual as the nodes form it (f(sigma_n) + S du, mpm_implicit affine_start) against the
   !> pass over the particles (im%node_forms = .false.), which forms sigma_p = sigma_n + E J_n d eps_p per
   !> particle: on the bar (hat, lumped; cpGIMP with the ghost penalty and the consistent mass), the driven
   !> composite bar and the quasi-static column (B-spline, mirror ghosts), after some steps of each form.
   subroutine affine_residual()
      type(config_t) :: config
      config = implicit_bar('linear', 2)
      call compare_affine(config, 8, 'bar, hat, lumped')
      config%shape = 'cpgimp'
      config%mass = 'consistent'
      config%ghost_penalty = 0.1_dp
      call compare_affine(config, 8, 'bar, cpgimp, consistent, ghost penalty')
      config = driven_composite('1.0e10', 20)
      config%integrator = 'implicit'
      config%dt_fraction = 5.0_dp
      call compare_affine(config, 8, 'composite bar, driven')
      config = column_config('linear', 'bspline2', 12, 4)
      call compare_affine(config, 3, 'column, bspline2, quasi-static')
   end subroutine affine_residual

   !> ln(1 + x) by its series (log_one_plus_series, through series_logarithms) against the quadruple-precision
   !> logarithm over |x| <= series_limit (log-uniform magnitudes from 1e-30, both signs, and the limits
   !> themselves): within 0.51 ulp of the exact value; below 2^-53 the value rounds to x itself (x^2/2 is under half its ulp),
   !> and ln(1 + 0) = 0.
   subroutine logarithm_series()
      real(dp) :: x, y, ulps, worst
      real(real128) :: exact
      integer :: k, sign_k
      worst = 0.0_dp
      do k = 0, 20000
         do sign_k = -1, 1, 2
            if (k == 20000) then
               x = sign_k*series_limit
            else
               x = sign_k*10.0_dp**(-30.0_dp + (30.0_dp + log10(series_limit))*k/20000.0_dp)
            end if
            y = sum(series_logarithms([x]))
            exact = reference(real(x, real128))
            ulps = real(abs(real(y, real128) - exact)/real(spacing(real(exact, dp)), real128), dp)
            worst = max(worst, ulps)
         end do
      end do
      call t%check('within 0.51 ulp of ln(1 + x) for |x| <= 2^-7 (worst '//str(worst)//' ulp)', worst <= 0.51_dp)
      call t%check('ln(1 + x) = x for tiny |x|', all(series_logarithms([1.0e-300_dp, -1.0e-20_dp, 1.0e-17_dp]) == &
                                                      [1.0e-300_dp, -1.0e-20_dp, 1.0e-17_dp]))
      call t%check('ln(1 + 0) = 0', all(series_logarithms([0.0_dp]) == 0.0_dp))
   end subroutine logarithm_series

   !> The hat's tangent formed and factored in one pass (tangent_factor_hat) against the tangent formed
   !> (tangent_hat) and then factored (banded_factor): the same factors, pivots, 1-norm, pivot extremes and
   !> info, bit for bit, with held rows at the ends and inside the grid, with none, with every row held,
   !> and where a column needs a row interchange or a pivot is zero (the two steps taken instead).
   subroutine fused_tangent_factor()
      integer, parameter :: n = 40
      real(dp) :: cells(3, 0:n - 1), mass(0:n)
      logical :: unknown(0:n)
      integer :: k
      do k = 0, n - 1
         cells(:, k) = [1.0e3_dp*(1.5_dp + sin(0.7_dp*k)), 0.0_dp, 0.0_dp]
      end do
      do k = 0, n
         mass(k) = 2.0e-3_dp*(1.2_dp + cos(1.3_dp*k))
      end do
      unknown = .true.
      call compare_factors(n, cells, unknown, mass, 'every row unknown', .true.)
      unknown([0, 17, 18, 25, n]) = .false.
      call compare_factors(n, cells, unknown, mass, 'held rows at the ends and inside', .true.)
      unknown = .false.
      call compare_factors(n, cells, unknown, mass, 'every row held', .true.)
      unknown = .true.
      unknown(0) = .false.
      cells(1, 9) = -4.0e3_dp ! |A(10, 9)| > A(9, 9): a row interchange
      call compare_factors(n, cells, unknown, mass, 'a column that needs an interchange', .false.)
      cells(1, 9) = 1.0e3_dp
      mass = 0.0_dp
      cells(1, :) = 0.0_dp ! a zero pivot (singular)
      call compare_factors(n, cells, unknown, mass, 'a zero pivot', .false.)
   end subroutine fused_tangent_factor

   !> fused_tangent_factor's comparison of the two ways for one tangent.
   subroutine compare_factors(n, cells, unknown, mass, label, fast)
      integer, intent(in) :: n
      real(dp), intent(in) :: cells(3, 0:n - 1), mass(0:n)
      logical, intent(in) :: unknown(0:n)
      character(len=*), intent(in) :: label
      logical, intent(in) :: fast !< whether the pivots can all be formed in the fused pass
      type(banded_t) :: fused, apart
      integer :: info_fused, info_apart
      real(dp), parameter :: inertia = 4.0_dp/0.3_dp**2
      call banded_init(fused, n + 1, 1, cleared=.false.)
      call banded_init(apart, n + 1, 1, cleared=.false.)
      fused%ab = -7.0_dp ! (whatever the last step left)
      call tangent_factor_hat(n, cells, unknown, inertia, mass, fused, info_fused)
      call tangent_hat(n, cells, unknown, inertia, mass, apart%ab)
      call banded_factor(apart, info_apart)
      call t%check(label//': the same factors bit for bit', all(fused%ab == apart%ab) .and. &
                   all(fused%pivots == apart%pivots), 'largest difference '// &
                   str(maxval(abs(fused%ab - apart%ab))))
      call t%check(label//': the same 1-norm, pivot extremes and info', fused%norm1 == apart%norm1 .and. &
                   fused%smallest_pivot == apart%smallest_pivot .and. fused%largest_pivot == apart%largest_pivot &
                   .and. info_fused == info_apart .and. (fused%factored .eqv. apart%factored) .and. &
                   (fused%interchanged .eqv. apart%interchanged), 'norm '//str(fused%norm1)//' '//str(apart%norm1)// &
                   ', pivots '//str(fused%smallest_pivot)//' '//str(apart%smallest_pivot)//' '// &
                   str(fused%largest_pivot)//' '//str(apart%largest_pivot)//', info '//str(info_fused)//' '// &
                   str(info_apart))
      call t%check(label//': '//trim(merge('factored without an interchange', 'an interchange or a zero pivot ', fast)), &
                   (apart%factored .and. .not. apart%interchanged) .eqv. fast)
   end subroutine compare_factors

   !> ln(1 + x) in quadruple precision: its series below |x| = 1e-3 (terms to x^16: a remainder below
   !> 1e-48 relative; 1 + x in quadruple precision would lose x's digits there), else the logarithm.
   real(real128) function reference(x)
      real(real128), intent(in) :: x
      integer :: k
      if (abs(x) >= 1.0e-3_real128) then
         reference = log(1.0_real128 + x)
         return
      end if
      reference = 0.0_real128
      do k = 16, 1, -1
         reference = x*((-1)**(k + 1)/real(k, real128) + reference)
      end do
   end function reference

   !> Hencky's residual on the hat with FLIP as its cells form it (mpm_implicit hencky_cells: the start's sums
   !> per cell, one logarithm a cell) against the pass over the particles, which forms each particle's
   !> sigma_n + E ln(1 + d eps): the bar at a strain amplitude where the logarithm is far from linear (lumped
   !> and consistent mass) and the driven composite bar (particles' own moduli, the drive's constraint).
   subroutine hencky_cells_residual()
      type(config_t) :: config
      config = implicit_bar('hencky', 3)
      call compare_affine(config, 8, 'hencky bar, hat, lumped')
      call compare_affine(config, 8, 'hencky bar, hat, lumped, cells of both signs', mixed=.true.)
      config%mass = 'consistent'
      call compare_affine(config, 8, 'hencky bar, hat, consistent')
      config = driven_composite('1.0e10', 20)
      config%integrator = 'implicit'
      config%law = 'hencky'
      config%dt_fraction = 5.0_dp
      call compare_affine(config, 8, 'hencky composite bar, driven')
   end subroutine hencky_cells_residual

   !> The bar of the node forms' comparisons: implicit, 16 elements of `ppe` particles, law `law`, at 60 m/s
   !> (a strain of about 1 %) and dt = 2 dx/c.
   function implicit_bar(law, ppe) result(config)
      character(len=*), intent(in) :: law
      integer, intent(in) :: ppe
      type(config_t) :: config
      config = new_config()
      config%integrator = 'implicit'
      config%law = law
      config%elements = 16
      config%particles_per_element = ppe
      call set_values(config, ['scene.velocity_amplitude=60.0'])
      config%dt_fraction = 2.0_dp
   end function implicit_bar

   !> compare_affine's check: after `steps` steps of each form from the same start, the positions,
   !> velocities and stresses agree to round-off of their scales and the solves are the same; then at one
   !> e off the solution (a random 1 % of the increment) both forms' residuals on the unknowns agree to
   !> round-off of the force scale, and their tangents to round-off of the largest entry.
   subroutine compare_affine(config, steps, label, mixed)
      type(config_t), intent(inout) :: config
      integer, intent(in) :: steps
      character(len=*), intent(in) :: label
      !> hencky_cells: the check's e has cells whose particles' stresses have both signs
      logical, intent(in), optional :: mixed
      class(scene_t), allocatable :: scene
      type(particles_t) :: pa, pp
      type(grid_t) :: grid
      type(shape_cache_t) :: cache
      type(material_t) :: material
      type(implicit_t) :: affine, particle
      type(pass_totals_t) :: totals
      real(dp), allocatable :: e(:), noise(:)
      real(dp) :: position, velocity, stress, residual, tangent, forces, roundoff
      integer :: n
      logical :: want_mixed
      want_mixed = .false.
      if (present(mixed)) want_mixed = mixed
      call setup(config, scene, pa, grid, cache, material)
      pp = pa
      call implicit_init(affine, config)
      call implicit_init(particle, config)
      particle%node_forms = .false.
      do n = 1, steps
         call implicit_advance(affine, scene, cache, pa, grid, config%dt, material, (n - 1)*config%dt, totals)
         call implicit_advance(particle, scene, cache, pp, grid, config%dt, material, (n - 1)*config%dt, totals)
      end do
      call t%check(label//': both forms converge, the same solves ('//str(affine%solves)//', '// &
                   str(particle%solves)//')', .not. (affine%failed .or. particle%failed) .and. &
                   affine%solves == particle%solves .and. affine%solves >= steps)
      position = maxval(abs(pa%x - pp%x))/maxval(abs(pp%x - pp%x0))
      velocity = maxval(abs(pa%v - pp%v))/max(maxval(abs(pp%v)), tiny(1.0_dp))
      stress = maxval(abs(pa%stress - pp%stress))/maxval(abs(pp%stress))
      call t%check(label//': the runs agree to round-off (displacement '//str(position)//', velocity '// &
                   str(velocity)//', stress '//str(stress)//')', max(position, velocity, stress) < 1.0e-11_dp)
      ! one e, both forms, from the particles of the particle form's run (want_mixed: their stresses made
      ! to differ within a cell, as particles that crossed into it from others or of other moduli have)
      if (want_mixed) then
         allocate (noise(pp%count))
         call random_number(noise)
         pp%stress = pp%stress*(0.5_dp + noise)
         deallocate (noise)
      end if
      call prepare_step(affine, scene, cache, pp, grid, config%dt, material, steps*config%dt, totals)
      call prepare_step(particle, scene, cache, pp, grid, config%dt, material, steps*config%dt, totals)
      call newton_solve(particle, cache, pp, grid, material)
      allocate (noise(0:grid%elements))
      call random_number(noise)
      e = particle%e + 0.01_dp*(noise - 0.5_dp)*maxval(abs(particle%du))
      if (want_mixed) e = straddling(particle, pp, cache, grid, config%dt, material%youngs_modulus)
      affine%e = merge(e, affine%e, affine%unknown)
      particle%e = merge(e, particle%e, particle%unknown)
      call assemble_system(affine, cache, pp, grid, material, with_tangent=.true.)
      call assemble_system(particle, cache, pp, grid, material, with_tangent=.true.)
      residual = maxval(abs(affine%residual - particle%residual), mask=particle%unknown)/ &
                 maxval(particle%forces, mask=particle%unknown)
      tangent = maxval(abs(affine%tangent%ab - particle%tangent%ab))/maxval(abs(particle%tangent%ab))
      call t%check(label//': the residual on the nodes = the particles'' to round-off ('//str(residual)//')', &
                   (affine%affine .or. affine%hencky_cells) .and. .not. (particle%affine .or. particle%hencky_cells) &
                   .and. residual < 1.0e-13_dp .and. &
                   maxval(abs(particle%residual), mask=particle%unknown) > 1.0e-6_dp* &
                   maxval(particle%forces, mask=particle%unknown))
      call t%check(label//': the tangents agree to round-off ('//str(tangent)//')', tangent < 1.0e-13_dp)
      if (affine%hencky_cells) then
         ! (the force scale: the particles' sum of |dN sigma V|, here formed per cell, and the round-off scale)
         forces = maxval(abs(affine%forces - particle%forces), mask=particle%unknown)/ &
                  maxval(particle%forces, mask=particle%unknown)
         roundoff = maxval(abs(affine%roundoff - particle%roundoff), mask=particle%unknown)/ &
                    maxval(particle%roundoff, mask=particle%unknown)
         call t%check(label//': the force and round-off scales agree to round-off ('//str(forces)//', '// &
                      str(roundoff)//'; cells of both signs: '//str(count(affine%mixed))//')', &
                      max(forces, roundoff) < 1.0e-13_dp .and. (count(affine%mixed) > 0 .or. .not. want_mixed))
      end if
   end subroutine compare_affine

   !> An e whose every cell's ln(1 + d eps) is minus the middle of its particles' sigma^n/E: their stresses
   !> sigma^n + E ln(1 + d eps) then have both signs (cells without particles: no strain).
   function straddling(im, pp, cache, grid, dt, modulus) result(e)
      type(implicit_t), intent(in) :: im
      type(particles_t), intent(in) :: pp
      type(shape_cache_t), intent(in) :: cache
      type(grid_t), intent(in) :: grid
      real(dp), intent(in) :: dt, modulus
      real(dp) :: e(0:grid%elements), lo(0:grid%elements - 1), hi(0:grid%elements - 1), du
      integer :: p, i
      lo = huge(1.0_dp)
      hi = -huge(1.0_dp)
      do p = 1, pp%count
         i = cache%first(p)
         lo(i) = min(lo(i), pp%stress(p)/modulus)
         hi(i) = max(hi(i), pp%stress(p)/modulus)
      end do
      du = 0.0_dp
      e(0) = im%e(0)
      do i = 0, grid%elements - 1
         if (hi(i) >= lo(i)) du = du + grid%dx*(exp(-0.5_dp*(lo(i) + hi(i))) - 1.0_dp)
         e(i + 1) = du - dt*im%velocity(i + 1)
      end do
   end function straddling

   !> The linear law is linear in the increment (sigma = sigma_n + E J_n d eps): one solve per step, at a
   !> tolerance of 1e-12 and a strain amplitude of 1e-8, where the stress E (J - 1) formed from a J stored
   !> near 1 would carry an absolute error E eps = 1e-8 of the stress amplitude and stop Newton at that floor.
   subroutine one_solve_for_a_linear_law()
      type(config_t) :: config
      type(run_result_t) :: r
      config%integrator = 'implicit'
      config%law = 'linear'
      config%elements = 20
      config%dt_fraction = 1.0_dp
      config%newton_tolerance = 1.0e-12_dp
      config%max_newton_iterations = 4
      call set_value(config, 'scene.velocity_amplitude='//str(1.0e-8_dp*sqrt(200.0e9_dp/7800.0_dp)))
      config%periods = 1.0_dp
      r = run_resolved(config)
      call t%check('linear law, strain 1e-8, tolerance 1e-12: completes', r%status == status_ok, &
                   guard_message(r%status, r%trip, config))
      call t%check_close('linear law: one linear solve per step', reported(r, 'newton_iterations'), 1.0_dp, &
                         atol=0.0_dp)
      call t%check_close('linear law: at most one solve in any step', reported(r, 'newton_iterations_max'), 1.0_dp, &
                         atol=0.0_dp)
   end subroutine one_solve_for_a_linear_law

   !> Newton's quadratic convergence on the Hencky column in one load step (30 % strain at the fixed end):
   !> the relative residuals fall to the tolerance within 6 solves, and each one after the first is at most
   !> 10 times the square of the one before (a tangent off by a relative delta gives r_{k+1} ~ delta r_k).
   subroutine quadratic_convergence()
      type(config_t) :: config
      class(scene_t), allocatable :: scene
      type(particles_t) :: particles
      type(grid_t) :: grid
      type(shape_cache_t) :: cache
      type(material_t) :: material
      type(implicit_t) :: im
      type(pass_totals_t) :: totals
      real(dp) :: worst
      integer :: k
      character(len=:), allocatable :: ratios
      config = column_config('hencky', 'cpgimp', 40, 1)
      config%newton_tolerance = 1.0e-14_dp
      call setup(config, scene, particles, grid, cache, material)
      call implicit_init(im, config)
      call implicit_advance(im, scene, cache, particles, grid, config%dt, material, 0.0_dp, totals)
      call t%check('hencky column: Newton converges to 1e-14', .not. im%failed .and. im%iterations <= 6, &
                   'solves '//str(im%iterations))
      worst = 0.0_dp
      ratios = ''
      do k = 1, im%iterations
         ratios = ratios//' '//str(im%residuals(k))
         ! (above the round-off floor, where the residual stops falling)
         if (im%residuals(k - 1) < 0.1_dp .and. im%residuals(k) > 1.0e-12_dp) &
            worst = max(worst, im%residuals(k)/im%residuals(k - 1)**2)
      end do
      call t%check('hencky column: r_{k+1} <= 10 r_k^2 (residuals'//ratios//')', worst <= 10.0_dp .and. &
                   im%iterations >= 3, 'largest r_{k+1}/r_k^2 '//str(worst))
   end subroutine quadratic_convergence

   !> Newmark's trapezoidal rule is second order: the linear bar's u_cm history on a fixed mesh (20
   !> elements) at dt_fraction 2, 1, 0.5, 0.25; the differences of successive histories at their common
   !> times fall by 4 (self-convergence order 2).
   subroutine temporal_order()
      type(config_t) :: config
      type(run_result_t) :: r(4), reference
      real(dp) :: difference(3), order
      integer :: k
      do k = 1, 4
         config = new_config()
         config%integrator = 'implicit'
         config%law = 'linear'
         config%elements = 20
         config%dt_fraction = 2.0_dp/2**(k - 1)
         config%periods = 0.5_dp
         r(k) = run_resolved(config)
      end do
      do k = 1, 3
         difference(k) = maxval(abs(r(k)%history%ucm - r(k + 1)%history%ucm(0::2)))
      end do
      do k = 1, 2
         order = log(difference(k)/difference(k + 1))/log(2.0_dp)
         call t%check('trapezoidal rule: self-convergence order 2 in dt ('//str(difference(k))//' -> '// &
                      str(difference(k + 1))//' m)', abs(order - 2.0_dp) < 0.1_dp, 'order '//str(order))
      end do
      ! ... and to the explicit schemes' limit: the same semi-discrete system (lumped mass, FLIP), so the
      ! finest implicit history lies within its own temporal error of MUSL at an 8 times smaller step
      config = new_config()
      config%law = 'linear'
      config%scheme = 'musl'
      config%elements = 20
      config%dt_fraction = 0.25_dp/8
      config%periods = 0.5_dp
      reference = run_resolved(config)
      order = maxval(abs(r(4)%history%ucm - reference%history%ucm(0::8)))
      call t%check('trapezoidal rule tends to the explicit limit (difference '//str(order)//' m, below the '// &
                   'last self-convergence difference '//str(difference(3))//' m)', order < difference(3))
   end subroutine temporal_order

   !> Beyond every explicit limit (USL 0.71, USF 2.0 dx/c at one particle per cell): dt_fraction 4 and 8
   !> complete, energy never above its start.
   subroutine beyond_the_explicit_limit()
      type(config_t) :: config
      type(run_result_t) :: r
      real(dp) :: fraction
      integer :: k
      do k = 1, 2
         fraction = 4.0_dp*k
         config = new_config()
         config%integrator = 'implicit'
         config%law = 'linear'
         config%elements = 40
         config%dt_fraction = fraction
         config%periods = 4.0_dp
         r = run_resolved(config)
         call t%check('dt_fraction '//str(fraction)//' completes', r%status == status_ok .and. &
                      r%steps_done == r%steps, status_name(r%status))
         call t%check('dt_fraction '//str(fraction)//': energy never grows', r%max_energy_ratio <= 1.0_dp + 1.0e-12_dp, &
                      'max energy ratio '//str(r%max_energy_ratio))
         call t%check('dt_fraction '//str(fraction)//': u_cm error below 50 % of the amplitude', &
                      r%relative_error < 0.5_dp, 'relative error '//str(r%relative_error))
      end do
   end subroutine beyond_the_explicit_limit

   !> The trapezoidal rule conserves the energy of a linear system: with the consistent mass the bar's
   !> kinetic + strain energy of the particles stays at its start to 1e-9 over 20 periods at dt = 2 dx/c
   !> (FLIP's particle kinetic energy changes by dv^T M v_n + dv^T M dv/2 with the integrator's M); the lumped
   !> mass loses dv^T (M_L - M_C) dv/2 per step and never gains.
   subroutine energy()
      type(config_t) :: config
      type(run_result_t) :: r
      real(dp) :: drift
      config%integrator = 'implicit'
      config%law = 'linear'
      config%mass = 'consistent'
      config%elements = 20
      config%dt_fraction = 2.0_dp
      config%periods = 20.0_dp
      r = run_resolved(config)
      drift = maxval(abs(r%history%kinetic_energy + r%history%strain_energy - r%initial_energy))/r%initial_energy
      call t%check('consistent mass: energy conserved to 1e-9 over 20 periods', drift < 1.0e-9_dp, &
                   'largest drift '//str(drift))
      config%mass = 'lumped'
      r = run_resolved(config)
      drift = (r%final_energy - r%initial_energy)/r%initial_energy
      call t%check('lumped mass: energy never grows', r%max_energy_ratio <= 1.0_dp + 1.0e-12_dp, &
                   'max energy ratio '//str(r%max_energy_ratio))
      call t%check('lumped mass: it loses some (the FLIP transfer)', drift < -1.0e-4_dp, 'drift '//str(drift))
   end subroutine energy

   !> The quasi-static column against its closed forms (mpm_scene_column).
   subroutine static_column()
      type(config_t) :: config
      type(run_result_t) :: r, coarse, fine
      real(dp) :: a, order
      character(len=16), parameter :: laws(3) = [character(len=16) :: 'linear', 'hencky', 'elastoplastic']
      integer :: k
      ! one particle per cell, linear shapes, one load step: the nodal values are exact
      config = column_config('linear', 'linear', 10, 1)
      config%particles_per_element = 1
      call set_values(config, ['scene.gravity=3.0e4'])
      r = run_resolved(config)
      select type (column => config%scene)
      type is (column_input_t)
         a = column%density*column%gravity/column%youngs_modulus
         call t%check_close('static column, linear law, hat, 1 ppc: error = (rho g/E) dx^2/8', r%max_error, &
                            a*(column%length/config%elements)**2/8, rtol=1.0e-9_dp)
      end select
      call t%check('static column: the converged state is a snapshot at full load', size(r%snapshots) == 1)
      if (size(r%snapshots) == 1) call t%check_close('static column: snapshot at load factor 1', &
                                                     r%snapshots(1)%time, 1.0_dp, atol=1.0e-12_dp)
      ! 30 % strain, cpGIMP, 10 load steps: second order for each law, over two doublings (20 -> 80
      ! elements; one doubling is erratic: the errors move by up to 2x as the particles' domains cross nodes)
      do k = 1, size(laws)
         coarse = run_resolved(column_config(trim(laws(k)), 'cpgimp', 20, 10))
         fine = run_resolved(column_config(trim(laws(k)), 'cpgimp', 80, 10))
         order = log(coarse%max_error/fine%max_error)/log(4.0_dp)
         call t%check('static column '//trim(laws(k))//', cpgimp, 30 % strain: completes', &
                      coarse%status == status_ok .and. fine%status == status_ok)
         call t%check('static column '//trim(laws(k))//', cpgimp: order 2 (errors '//str(coarse%max_error)//', '// &
                      str(fine%max_error)//' m)', order > 1.8_dp .and. order < 2.3_dp, 'order '//str(order))
      end do
   end subroutine static_column

   function column_config(law, shape, elements, load_steps) result(config)
      character(len=*), intent(in) :: law, shape
      integer, intent(in) :: elements, load_steps
      type(config_t) :: config
      config%integrator = 'quasi_static'
      call set_values(config, ["scene.kind='column'"])
      config%law = law
      config%shape = shape
      config%elements = elements
      config%particles_per_element = 2
      call set_values(config, ['scene.length=1.0'])
      call set_values(config, ['scene.youngs_modulus=1.0e10'])
      call set_values(config, ['scene.density=1000.0'])
      call set_values(config, ['scene.gravity=3.0e6'])
      config%load_steps = load_steps
      config%max_cell_move = 100.0_dp
      if (law == 'elastoplastic') then
         call set_values(config, ['material.yield_stress=1.0e9'])
         call set_values(config, ['material.hardening_modulus=2.0e9'])
      end if
   end function column_config

   !> The composite bar of the drives' tests: a soft segment (E 1e8) driven at 0.01 m/s, then a stiff one
   !> (Young's modulus `stiff`), law linear, 2 particles per element.
   function driven_composite(stiff, elements) result(config)
      character(len=*), intent(in) :: stiff
      integer, intent(in) :: elements
      type(config_t) :: config
      call set_values(config, ["scene.kind='composite_bar'"])
      call set_values(config, ['scene.lengths=0.5, 0.5'])
      call set_value(config, 'scene.youngs_moduli=1.0e8, '//stiff)
      call set_values(config, ['scene.densities=1000.0, 1000.0'])
      call set_values(config, ['scene.drive_velocity=0.01'])
      config%law = 'linear'
      config%elements = elements
      config%particles_per_element = 2
   end function driven_composite

   !> The drives: the composite bar (a soft segment driven at 0.01 m/s, a stiff one 100 times faster) at
   !> 100 elements: implicit at dt = 0.5 dx/c_soft (50 times the explicit step) has a u_cm error within
   !> twice explicit USL's at dt = 0.5 dx/c_stiff (the driven node moves at V over the whole step: the
   !> trapezoidal average of the start's jump would leave it V dt/2 behind, a 7e-3 error); the elastoplastic
   !> plastic wave (end particle driven, two fronts) within 20 % of explicit's L1 stress error; at 32 times
   !> the step it completes, where Newton without its line search cycles (seen: relative residual 0.4 after
   !> 25 solves at step 3).
   subroutine drives()
      type(config_t) :: config
      type(run_result_t) :: explicit, implicit
      real(dp) :: ucm_explicit, ucm_implicit
      config = driven_composite('1.0e12', 100)
      config%end_time = 1.5_dp*0.5_dp/sqrt(1.0e8_dp/1000.0_dp)
      config%periods_given = .false.
      config%end_time_given = .true.
      config%dt_fraction = 0.5_dp
      explicit = run_resolved(config)
      config%integrator = 'implicit'
      config%dt_fraction = 50.0_dp
      implicit = run_resolved(config)
      ucm_explicit = maxval(abs(explicit%history%ucm - explicit%history%ucm_exact))/ &
                     maxval(abs(explicit%history%ucm_exact))
      ucm_implicit = maxval(abs(implicit%history%ucm - implicit%history%ucm_exact))/ &
                     maxval(abs(implicit%history%ucm_exact))
      call t%check('composite, implicit at 50x the explicit step: completes in 1 solve per step', &
                   implicit%status == status_ok .and. reported(implicit, 'newton_iterations_max') == 1.0_dp)
      call t%check('composite: implicit u_cm error within 2x explicit''s ('//str(ucm_implicit)//', '// &
                   str(ucm_explicit)//')', ucm_implicit < 2*ucm_explicit, 'implicit '//str(ucm_implicit))
      config = new_config()
      call set_values(config, ["scene.kind='plastic_wave'"])
      call set_values(config, ['scene.length=1.0'])
      call set_values(config, ['scene.youngs_modulus=1.0e10'])
      call set_values(config, ['scene.density=1000.0'])
      call set_values(config, ['scene.drive_velocity=5.0'])
      config%law = 'elastoplastic'
      call set_values(config, ['material.yield_stress=1.0e7'])
      call set_values(config, ['material.hardening_modulus=1.0e9'])
      config%elements = 100
      config%particles_per_element = 2
      config%periods = 0.8_dp
      config%dt_fraction = 0.5_dp
      explicit = run_resolved(config)
      config%integrator = 'implicit'
      implicit = run_resolved(config)
      call t%check('plastic wave, implicit: L1 stress error within 20 % of explicit''s ('// &
                   str(implicit%relative_error)//', '//str(explicit%relative_error)//')', &
                   implicit%status == status_ok .and. implicit%relative_error < 1.2_dp*explicit%relative_error)
      config%dt_fraction = 16.0_dp
      call resolve_config(config)
      implicit = run_resolved(config)
      call t%check('plastic wave, implicit at 32x the step: completes (line search: '// &
                   str(reported(implicit, 'newton_halvings'))//' halvings)', implicit%status == status_ok, &
                   guard_message(implicit%status, implicit%trip, config))
   end subroutine drives

   !> A step that does not converge stops the run with its own status, naming step, solves and residual.
   subroutine newton_guard()
      type(config_t) :: config
      type(run_result_t) :: r
      character(len=:), allocatable :: message
      config = column_config('hencky', 'linear', 10, 2)
      config%max_newton_iterations = 1
      call resolve_config(config)
      r = run_resolved(config)
      message = guard_message(r%status, r%trip, config)
      call t%check('one solve for the nonlinear column: status newton_not_converged', r%status == status_newton, &
                   status_name(r%status))
      call t%check('stopped at step 1, nothing completed', r%trip%step == 1 .and. r%steps_done == 0)
      call t%check_contains('message names the guard and step', message, &
                            'guard newton_not_converged tripped at step 1 of 2')
      call t%check_contains('message names the solves', message, 'after 1 linear solves')
      call t%check_contains('message names the residual', message, 'relative residual '//str(r%trip%value))
      call t%check('the residual is a real, unconverged one', r%trip%value > config%newton_tolerance .and. &
                   r%trip%value < 1.0_dp)
   end subroutine newton_guard

   !> A variable of another integrator is refused naming both, the scenes an integrator cannot run are
   !> refused, dt_fraction's limit follows the integrator, and the echo reads back.
   subroutine namelist()
      type(config_t) :: config, again
      type(error_t), allocatable :: error
      call read_config_text("&discretisation integrator='implicit', scheme='musl' /", 'test', config, error)
      call expect_refusal(error, "'scheme' is not used by integrator = 'implicit'; it belongs to integrator explicit")
      call read_config_text("&discretisation integrator='implicit', load_steps=5 /", 'test', config, error)
      call expect_refusal(error, "'load_steps' is not used by integrator = 'implicit'; it belongs to integrator quasi_static")
      call read_config_text("&discretisation newton_tolerance=1e-8 /", 'test', config, error)
      call expect_refusal(error, "'newton_tolerance' is not used by integrator = 'explicit'; it belongs to integrator "// &
                          "implicit, quasi_static")
      call read_config_text("&scene kind='column' / &discretisation integrator='quasi_static', dt_fraction=0.5 /", &
                            'test', config, error)
      call expect_refusal(error, "'dt_fraction' is not used by integrator = 'quasi_static'")
      call read_config_text("&discretisation integrator='quasi_static' /", 'test', config, error)
      call expect_refusal(error, "integrator = 'quasi_static' needs a scene with static loads")
      call read_config_text("&scene kind='impact', lengths=1,1, youngs_moduli=1e9,1e9, densities=1e3,1e3, "// &
                            "velocities=1,-1 / &discretisation integrator='implicit' /", 'test', config, error)
      call expect_refusal(error, "contact = 'frictionless' is not used by integrator = 'implicit'")
      call read_config_text("&discretisation dt_fraction=20 /", 'test', config, error)
      call expect_refusal(error, "dt_fraction = 20")
      call read_config_text("&discretisation integrator='implicit', dt_fraction=1000, elements=2000 /", 'test', &
                            config, error)
      call t%check('implicit takes dt_fraction = 1000', .not. allocated(error))
      call read_config_text("&discretisation integrator='implicit', mass='consistent', dt_fraction=4 / "// &
                            "&material law='linear' /", 'test', config, error)
      call t%check('implicit configuration read', .not. allocated(error))
      call read_config_text(config_namelist(config), 'echo', again, error)
      call t%check('implicit echo reads back', .not. allocated(error) .and. again%integrator == 'implicit' .and. &
                   again%mass == 'consistent' .and. again%dt_fraction == 4.0_dp)
      call read_config_text("&scene kind='column' / &discretisation integrator='quasi_static', load_steps=7 /", &
                            'test', config, error)
      call t%check('quasi_static configuration read', .not. allocated(error) .and. config%steps == 7)
      call read_config_text(config_namelist(config), 'echo', again, error)
      call t%check('quasi_static echo reads back', .not. allocated(error) .and. again%load_steps == 7 .and. &
                   again%steps == 7)
   end subroutine namelist

   subroutine expect_refusal(error, part)
      type(error_t), allocatable, intent(in) :: error
      character(len=*), intent(in) :: part
      call t%check('refused: '//part, allocated(error))
      if (allocated(error)) call t%check_contains('message: '//part, error%message, part)
   end subroutine expect_refusal

   !> The cut cell: the bar's free end crossing into an empty cell with quadratic B-splines gives a nearly
   !> empty node; the ghost penalty raises the tangent's smallest reciprocal condition number by orders of
   !> magnitude and keeps the run's accuracy. The quasi-static column whose top sits 0.8 cells into a span at
   !> the second load step (one particle per cell): without the penalty the tangent is numerically singular
   !> (rcond 1e-11) and the run blows up (its top particle thrown out of the grid); with the default penalty
   !> it converges to 0.3 %.
   subroutine ghost_penalty_conditioning()
      type(config_t) :: config
      type(run_result_t) :: plain, penalised
      config%integrator = 'implicit'
      config%shape = 'bspline2'
      config%elements = 40
      call set_values(config, ['scene.velocity_amplitude=30.0'])
      config%dt_fraction = 1.0_dp
      config%periods = 0.5_dp
      config%ghost_penalty = 0.0_dp
      plain = run_resolved(config)
      config%ghost_penalty = -1.0_dp ! the default: 0.1 for B-splines
      penalised = run_resolved(config)
      call t%check('cut cell without the penalty: rcond below 1e-4', reported(plain, 'tangent_rcond_min') < 1.0e-4_dp, &
                   'rcond '//str(reported(plain, 'tangent_rcond_min')))
      call t%check('ghost penalty (default for B-splines): rcond above 1e-3', &
                   reported(penalised, 'tangent_rcond_min') > 1.0e-3_dp, &
                   'rcond '//str(reported(penalised, 'tangent_rcond_min')))
      call t%check('ghost penalty keeps the accuracy (within 20 %)', &
                   penalised%relative_error < 1.2_dp*plain%relative_error, &
                   str(penalised%relative_error)//' against '//str(plain%relative_error))
      config = column_config('linear', 'bspline2', 20, 2)
      config%particles_per_element = 1
      call set_values(config, ['scene.gravity=1.6e6'])
      config%ghost_penalty = 0.0_dp
      plain = run_resolved(config)
      config%ghost_penalty = -1.0_dp
      penalised = run_resolved(config)
      call t%check('quasi-static cut cell without the penalty: the run fails or is off by more than 10 %', &
                   plain%status /= status_ok .or. plain%relative_error > 0.1_dp, &
                   status_name(plain%status)//', relative error '//str(plain%relative_error))
      call t%check('quasi-static cut cell with the penalty: completes within 1 %', penalised%status == status_ok &
                   .and. penalised%relative_error < 0.01_dp, status_name(penalised%status)//', relative error '// &
                   str(penalised%relative_error))
   end subroutine ghost_penalty_conditioning


   real(dp) function reported(r, name)
      type(run_result_t), intent(in) :: r
      character(len=*), intent(in) :: name
      integer :: i
      reported = -1.0_dp
      do i = 1, size(r%report_names)
         if (trim(r%report_names(i)) == name) reported = r%report_values(i)
      end do
   end function reported
end program test_implicit
