!> A column under its own weight, suddenly loaded: length L on [0, L], fixed at x = 0, free at x = L,
!> at rest and unstressed at t = 0, body force -g per unit mass (towards the fixed end) from t = 0.
!> Exact (linear elasticity, c^2 = E/rho; separation of variables as for the bar, e.g. Graff, Wave
!> Motion in Elastic Solids, 1975, sec. 2.2): u(x,t) = u_s(x) + sum_n a_n sin(beta_n x) cos(omega_n t),
!>   u_s(x) = -(g/c^2)(L x - x^2/2)  (the static solution: u_s(0) = 0, u_s'(L) = 0),
!>   beta_n = (2n-1) pi/(2L), omega_n = beta_n c,
!>   a_n = -(2/L) int_0^L u_s sin(beta_n x) dx = 2 g/(c^2 L beta_n^3)  (u(x,0) = 0).
!> Centre of mass (1/L) int_0^L u dx, with int_0^L sin(beta_n x) dx = 1/beta_n:
!>   u_cm(t) = -g L^2/(3 c^2) + sum_n 2 g/(c^2 L^2 beta_n^4) cos(omega_n t)
!>           = -g L^2/(3 c^2) + (32 g L^2/(pi^4 c^2)) S(omega_1 t),  S(th) = sum_n cos((2n-1) th)/(2n-1)^4,
!> and the series S in closed form (integrating twice sum_n cos((2n-1) th)/(2n-1)^2 = pi(pi - 2|th|)/8,
!> |th| <= pi): S(th) = pi^4/96 - pi (pi th^2/2 - th^3/3)/8 on [0, pi], even and 2 pi-periodic, with
!> S(2 pi - th) = S(th). So u_cm swings between 0 and -2 g L^2/(3 c^2): its amplitude is g L^2/(3 c^2).
!> The sum to round-off and the closed form agree (test_scenes_exact). Needs the external force on the grid:
!> f_I += m_I (-g) (the lumped mass carries sum_p N_Ip m_p (-g) exactly, since sum_I N_Ip = 1).
!>
!> Static (integrator = 'quasi_static', mpm_implicit): equilibrium under the fraction lambda of the
!> weight (g -> lambda g), at any strain and for each law. In 1-D with unit area the first Piola-Kirchhoff
!> stress is the Cauchy stress, so dsigma/dX = rho0 g with sigma(L) = 0 (the free end) gives
!> sigma(X) = -rho0 g (L - X) whatever the law (the column is statically determinate), and the law gives
!> J(X) = dx/dX, x(X) = int_0^X J:
!>   linear         J = 1 + sigma/E: u_s(X) = -(rho0 g/E)(L X - X^2/2), exact at any strain;
!>   hencky         J = exp(sigma/E) = exp(-a (L - X)), a = rho0 g/E:  x(X) = (exp(-a (L - X)) - exp(-a L))/a;
!>   elastoplastic  loaded monotonically from rest, ln J = sigma/E + eps_p with eps_p = -(|sigma| - sigma_y)/H
!>                  where |sigma| > sigma_y, i.e. below X_y = L - sigma_y/(rho0 g): there
!>                  ln J = -k (L - X) + sigma_y/H, k = rho0 g (1/E + 1/H), and
!>                  x(X) = exp(sigma_y/H) (exp(-k (L - X)) - exp(-k L))/k; above X_y the hencky form from
!>                  x(X_y). Perfectly plastic (H = 0) with |sigma| > sigma_y somewhere: no equilibrium (NaN).
!> Its error measure is then max_p |x_p - X_p - u_s(X_p)| at each load step (m), relative to |u_s(L)| at
!> full load, and u_cm,exact the mean (1/L) int_0^L u_s dX (Gauss-Legendre, to round-off).
module mpm_scene_column
   use, intrinsic :: ieee_arithmetic, only: ieee_value, ieee_quiet_nan
   use mpm_kinds, only: dp, pi
   use mpm_errors, only: error_t, append_error
   use mpm_strings, only: str, num, num_at_least
   use mpm_settings, only: settings_t
   use mpm_registry, only: parameter_t, real_entry, short_number
   use mpm_grid, only: grid_t, grid_loads_t
   use mpm_particles, only: particles_t, particles_init
   use mpm_shape, only: shape_cache_t
   use mpm_particle_forces, only: p2g_particle_forces
   use mpm_material, only: material_t, law_linear, law_elastoplastic
   use mpm_scene, only: scene_t, margin_for, exact_name_length
   use mpm_scene_input, only: scene_input_t, scene_kind_t, body_input_t, body_representable
   implicit none
   private
   public :: column_t, column_init, column_series, column_input_t

   !> The column's input: its body and the gravitational acceleration g.
   type, extends(body_input_t) :: column_input_t
      real(dp) :: gravity = 9.81_dp
   contains
      procedure, nopass :: describe => column_describe
      procedure :: entries => column_entries
      procedure :: amplitude_source => column_amplitude_source
      procedure :: period => column_period
      procedure :: reach => column_reach
      procedure :: static_loads => column_static_loads
      procedure :: check => column_check
      procedure :: check_representable => column_representable
      procedure :: make => column_make
   end type column_input_t

   type, extends(scene_t) :: column_t
      real(dp) :: length = 0.0_dp
      real(dp) :: gravity = 0.0_dp
      real(dp) :: density = 0.0_dp
      real(dp) :: wave_speed = 0.0_dp
      real(dp) :: omega = 0.0_dp      !< omega_1 = pi c/(2L) (rad/s)
      real(dp) :: amplitude = 0.0_dp  !< g L^2/(3 c^2): the u_cm swing's half range and mean offset (m)
      !> the static problem (integrator quasi_static: "time" is the load factor) and the law it is solved with
      logical :: static = .false.
      type(material_t) :: material
   contains
      procedure :: place_particles, margin_cells, fixed_nodes, ucm_exact, ucm_amplitude
      procedure :: add_forces, energy_reference, report, error_at, error_name, fused_applies, grid_loads
      procedure :: static_displacement, exact_fields
   end type column_t

contains

   pure function column_describe() result(kind)
      type(scene_kind_t) :: kind
      kind = scene_kind_t('column', 'a column under its own weight, suddenly loaded', '4L/c')
   end function column_describe

   subroutine column_entries(self, table)
      class(column_input_t), intent(inout), target :: self
      type(parameter_t), allocatable, intent(out) :: table(:)
      call self%body_entries(table)
      table = [table, real_entry('scene', 'gravity', self%gravity, 'm/s^2', 'gravitational acceleration g: body '// &
                                 'force -g per unit mass, towards the fixed end x = 0', greater_than=0.0_dp, &
                                 sweep_list='gravities')]
   end subroutine column_entries

   !> Its first mode's period, 4L/c.
   pure real(dp) function column_period(self)
      class(column_input_t), intent(in) :: self
      column_period = 4.0_dp*self%length/sqrt(self%youngs_modulus/self%density)
   end function column_period

   !> Its sag g L^2/c^2.
   pure real(dp) function column_reach(self, end_time)
      class(column_input_t), intent(in) :: self
      real(dp), intent(in) :: end_time
      column_reach = self%gravity*self%length**2/self%wave_speed()**2
   end function column_reach

   !> The column's weight at its fixed end, rho g L: a perfectly plastic column yielding there has no
   !> equilibrium (docs/theory.md, The static column): it flows without bound (a quasi-static run left the
   !> grid at x = 3.5e10 m, an explicit one tripped the energy guard).
   subroutine column_check(self, settings, error, given)
      class(column_input_t), intent(in) :: self
      class(settings_t), intent(in) :: settings
      type(error_t), allocatable, intent(inout) :: error
      type(parameter_t), intent(in), optional :: given(:)
      real(dp) :: weight
      if (trim(settings%law) /= 'elastoplastic' .or. self%hardening_modulus /= 0.0_dp) return
      weight = self%density*self%gravity*self%length
      if (self%yield_stress < weight) &
         call append_error(error, "material: hardening_modulus = 0 (perfectly plastic) with yield_stress = "// &
                           short_number(self%yield_stress)//" Pa, below the column's weight at its fixed end "// &
                           "rho g L = "//num(weight, 4)//" Pa: the column yields and has no equilibrium; allowed: "// &
                           "yield_stress >= "//num_at_least(weight, 4)//" Pa, or hardening_modulus > 0")
   end subroutine column_check

   !> Its weight is a static load with an exact static solution (integrator 'quasi_static').
   pure logical function column_static_loads(self)
      class(column_input_t), intent(in) :: self
      column_static_loads = .true.
   end function column_static_loads

   !> Beyond the wave speed (body_input_t): a strain g L rho/E below 1 at the fixed end, and the products
   !> its exact solution and energies form as they stand within the doubles (compared as logarithms).
   subroutine column_representable(self, settings, error)
      class(column_input_t), intent(in) :: self
      class(settings_t), intent(in) :: settings
      type(error_t), allocatable, intent(inout) :: error
      real(dp), parameter :: top = log10(huge(1.0_dp)), bottom = log10(tiny(1.0_dp))
      real(dp) :: log_ratio, log_v
      call body_representable(self, settings, error)
      if (allocated(error)) return
      log_ratio = log10(self%youngs_modulus) - log10(self%density)
      ! strain at the fixed end rho g L/E = g L/c^2 (>= 1: J <= 0)
      log_v = log10(self%gravity) + log10(self%length) - log_ratio
      if (log_v >= 0.0_dp) then
         call append_error(error, "scene: gravity = "//short_number(self%gravity)//" m/s^2, length = "// &
                           short_number(self%length)//" m and "//material()//" give a strain g L rho/E = 1e"// &
                           str(nint(log_v))//" at the fixed end; allowed: gravity length density/youngs_modulus < 1")
         return
      end if
      call within("the sag g L^2/c^2", log_v + log10(self%length))
      call within("g L", log10(self%gravity) + log10(self%length))
      call within("L^3", 3*log10(self%length))
      call within("g^2", 2*log10(self%gravity))
      call within("the energy rho g^2 L^3/c^2", log10(self%density) + 2*log10(self%gravity) + &
                  3*log10(self%length) - log_ratio)
   contains
      !> Refuse the scene when a product its formulas form (log10 `magnitude`) leaves the doubles.
      subroutine within(what, magnitude)
         character(len=*), intent(in) :: what
         real(dp), intent(in) :: magnitude
         if (magnitude < bottom + 2 .or. magnitude > top - 2) call append_error(error, "scene: kind = 'column' "// &
            "with length = "//short_number(self%length)//" m, gravity = "//short_number(self%gravity)// &
            " m/s^2 and "//material()//": "//what//" is about 1e"//str(nint(magnitude))//", beyond what its "// &
            "formulas hold in doubles; allowed: 1e-306 to 1e306 (choose units nearer 1; the vibrating bar's "// &
            "formulas are scaled, these are not)")
      end subroutine within
      function material() result(text)
         character(len=:), allocatable :: text
         text = "youngs_modulus = "//short_number(self%youngs_modulus)//" Pa and density = "// &
                short_number(self%density)//" kg/m^3"
      end function material
   end subroutine column_representable

   subroutine column_make(self, settings, scene, error)
      class(column_input_t), intent(in) :: self
      class(settings_t), intent(in) :: settings
      class(scene_t), allocatable, intent(out) :: scene
      type(error_t), allocatable, intent(out) :: error
      allocate (scene, source=column_init(self%length, self%youngs_modulus, self%density, self%gravity, &
                                          static=trim(settings%integrator) == 'quasi_static', &
                                          material=self%material(settings%law)))
   end subroutine column_make

   pure function column_init(length, youngs_modulus, density, gravity, static, material) result(column)
      real(dp), intent(in) :: length, youngs_modulus, density, gravity
      !> the static problem (quasi_static) of the column of `material` (default: the dynamic one)
      logical, intent(in), optional :: static
      type(material_t), intent(in), optional :: material
      type(column_t) :: column
      if (present(static)) column%static = static
      column%material%youngs_modulus = youngs_modulus
      if (present(material)) column%material = material
      column%external_forces = .true.
      column%length = length
      column%gravity = gravity
      column%density = density
      column%wave_speed = sqrt(youngs_modulus/density)
      column%omega = pi*column%wave_speed/(2.0_dp*length)
      column%amplitude = gravity*length**2/(3.0_dp*column%wave_speed**2)
   end function column_init

   !> S(th) = sum_{n>=1} cos((2n-1) th)/(2n-1)^4 in closed form (see the module's comment).
   elemental real(dp) function column_series(theta) result(s)
      real(dp), intent(in) :: theta
      real(dp) :: th
      th = modulo(abs(theta), 2.0_dp*pi)
      if (th > pi) th = 2.0_dp*pi - th
      s = pi**4/96.0_dp - pi*(pi*th**2/2.0_dp - th**3/3.0_dp)/8.0_dp
   end function column_series

   !> As the bar's: `particles_per_element` particles per element at the centres of equal sub-cells, at rest.
   subroutine place_particles(self, settings, particles, error)
      class(column_t), intent(in) :: self
      class(settings_t), intent(in) :: settings
      type(particles_t), intent(out) :: particles
      type(error_t), allocatable, intent(out) :: error
      call particles_init(particles, settings%elements, settings%particles_per_element, settings%dx, self%density, error)
   end subroutine place_particles

   !> The free end moves towards the fixed one, by at most twice the static end displacement g L^2/(2 c^2)
   !> (the grid's span is enough); two cells beyond it for the shape support and slack, as the bar,
   !> plus the end's excursion in cells should gravity ever point the other way.
   pure integer function margin_cells(self, dx, requested) result(cells)
      class(column_t), intent(in) :: self
      real(dp), intent(in) :: dx
      integer, intent(in) :: requested
      cells = margin_for(abs(self%gravity)*self%length**2/self%wave_speed**2, dx, requested)
   end function margin_cells

   pure function fixed_nodes(self) result(nodes)
      class(column_t), intent(in) :: self
      integer, allocatable :: nodes(:)
      nodes = [0]
   end function fixed_nodes

   pure real(dp) function ucm_exact(self, t)
      class(column_t), intent(in) :: self
      real(dp), intent(in) :: t
      if (self%static) then
         ucm_exact = static_mean(self, t)
         return
      end if
      ucm_exact = -self%amplitude + 32.0_dp*self%gravity*self%length**2/(pi**4*self%wave_speed**2)* &
                  column_series(self%omega*t)
   end function ucm_exact

   pure real(dp) function ucm_amplitude(self)
      class(column_t), intent(in) :: self
      if (self%static) then
         ucm_amplitude = abs(self%static_displacement(self%length, 1.0_dp))
      else
         ucm_amplitude = self%amplitude
      end if
   end function ucm_amplitude

   !> The static displacement u_s(X) = x(X) - X under the fraction `load` of the weight (see the module),
   !> written as integrals of J - 1 so that a small strain keeps its digits (stretch_integral).
   elemental real(dp) function static_displacement(self, x0, load) result(u)
      class(column_t), intent(in) :: self
      real(dp), intent(in) :: x0, load
      real(dp) :: weight, a, k, x_yield, softening
      weight = self%density*load*self%gravity   ! rho0 g: the stress gradient
      a = weight/self%material%youngs_modulus
      x_yield = -1.0_dp
      if (self%material%law == law_elastoplastic) x_yield = self%length - self%material%yield_stress/weight
      if (self%material%law == law_linear) then
         u = -a*(self%length*x0 - 0.5_dp*x0**2)
      else if (x_yield <= 0.0_dp) then ! hencky, or elastoplastic nowhere yielded: ln J = -a (L - X)
         u = stretch_integral(-a*self%length, a, x0)
      else if (self%material%hardening_modulus <= 0.0_dp) then
         u = ieee_value(1.0_dp, ieee_quiet_nan)  ! perfectly plastic and yielded: no equilibrium
      else ! ln J = sigma_y/H - k (L - X) below X_y, -a (L - X) above
         softening = self%material%yield_stress/self%material%hardening_modulus
         k = weight*(1.0_dp/self%material%youngs_modulus + 1.0_dp/self%material%hardening_modulus)
         if (x0 <= x_yield) then
            u = stretch_integral(softening - k*self%length, k, x0)
         else
            u = stretch_integral(softening - k*self%length, k, x_yield) + &
                stretch_integral(-a*(self%length - x_yield), a, x0 - x_yield)
         end if
      end if
   end function static_displacement

   !> int_0^w (J(s) - 1) ds for J(s) = exp(log_start + rate s): exp(log_start) (exp(rate w) - 1 - rate w)/rate
   !> + (exp(log_start) - 1) w, free of cancellation for small strains.
   elemental real(dp) function stretch_integral(log_start, rate, w) result(integral)
      real(dp), intent(in) :: log_start, rate, w
      if (rate == 0.0_dp) then ! (no load)
         integral = exp_minus_one(log_start)*w
      else
         integral = exp(log_start)*exp_minus_linear(rate*w)/rate + exp_minus_one(log_start)*w
      end if
   end function stretch_integral

   !> exp(z) - 1 to a few ulps (Kahan's form: exp(z) - 1 scaled by z/ln(exp(z)); see Goldberg 1991, in
   !> mpm_material's log_one_plus).
   elemental real(dp) function exp_minus_one(z) result(y)
      real(dp), intent(in) :: z
      real(dp) :: e
      e = exp(z)
      if (e == 1.0_dp) then
         y = z
      else if (e - 1.0_dp == -1.0_dp) then
         y = -1.0_dp
      else
         y = (e - 1.0_dp)*z/log(e)
      end if
   end function exp_minus_one

   !> exp(z) - 1 - z: its Taylor series for |z| < 1/2 (terms to z^20, below eps z^2), else directly.
   elemental real(dp) function exp_minus_linear(z) result(y)
      real(dp), intent(in) :: z
      real(dp) :: term
      integer :: n
      if (abs(z) >= 0.5_dp) then
         y = exp_minus_one(z) - z
         return
      end if
      term = z
      y = 0.0_dp
      do n = 2, 20
         term = term*z/n
         y = y + term
      end do
   end function exp_minus_linear

   !> (1/L) int_0^L u_s dX under the fraction `load` of the weight, by 4-point Gauss-Legendre on 64 panels
   !> on each side of the yield depth (u_s is smooth on each side: to round-off).
   pure real(dp) function static_mean(self, load) result(mean)
      class(column_t), intent(in) :: self
      real(dp), intent(in) :: load
      real(dp), parameter :: nodes(4) = [-0.8611363115940526_dp, -0.3399810435848563_dp, 0.3399810435848563_dp, &
                                         0.8611363115940526_dp], &
                             weights(4) = [0.3478548451374538_dp, 0.6521451548625461_dp, 0.6521451548625461_dp, &
                                           0.3478548451374538_dp]
      integer, parameter :: panels = 64
      real(dp) :: split, a, b, h
      integer :: side, i
      split = 0.0_dp
      mean = 0.0_dp
      if (load <= 0.0_dp) return
      if (self%material%law == law_elastoplastic) &
         split = min(max(self%length - self%material%yield_stress/(self%density*load*self%gravity), 0.0_dp), &
                     self%length)
      mean = 0.0_dp
      do side = 1, 2
         a = merge(0.0_dp, split, side == 1)
         b = merge(split, self%length, side == 1)
         h = (b - a)/panels
         if (h <= 0.0_dp) cycle
         do i = 0, panels - 1
            mean = mean + 0.5_dp*h*sum(weights*self%static_displacement(a + h*(i + 0.5_dp + 0.5_dp*nodes), load))
         end do
      end do
      mean = mean/self%length
   end function static_mean

   !> The exact fields at X = x0. Static (t the load factor): u_s(X) and sigma = -t rho0 g (L - X). Dynamic
   !> (linear elasticity), d'Alembert's form of the module's series: w = u - u_s solves the wave equation
   !> with w(0) = 0, w_x(L) = 0, w(x, 0) = -u_s(x), w_t(x, 0) = 0, so w = (F(x - ct) + F(x + ct))/2 with F
   !> the extension of -u_s odd about 0 and even about L (period 4L): u = u_s + w, v = c (F'(x + ct) -
   !> F'(x - ct))/2, sigma = E (u_s' + (F'(x - ct) + F'(x + ct))/2).
   pure subroutine exact_fields(self, x0, t, names, values)
      class(column_t), intent(in) :: self
      real(dp), intent(in) :: x0(:), t
      character(len=exact_name_length), allocatable, intent(out) :: names(:)
      real(dp), allocatable, intent(out) :: values(:, :)
      real(dp) :: c, k
      integer :: p
      if (self%static) then
         names = [character(len=exact_name_length) :: 'displacement', 'stress']
         allocate (values(size(x0), 2))
         values(:, 1) = self%static_displacement(x0, t)
         values(:, 2) = -t*self%density*self%gravity*(self%length - x0)
         return
      end if
      names = [character(len=exact_name_length) :: 'displacement', 'velocity', 'stress']
      allocate (values(size(x0), 3))
      c = self%wave_speed
      k = self%gravity/c**2
      do p = 1, size(x0)
         associate (x => x0(p))
            values(p, 1) = -k*(self%length*x - x**2/2.0_dp) + 0.5_dp*(extension(x - c*t) + extension(x + c*t))
            values(p, 2) = 0.5_dp*c*(slope(x + c*t) - slope(x - c*t))
            values(p, 3) = self%density*c**2*(-k*(self%length - x) + 0.5_dp*(slope(x - c*t) + slope(x + c*t)))
         end associate
      end do
   contains
      !> F(s): -u_s(s) = k (L s - s^2/2) on [0, L], odd about 0, even about L, period 4L.
      pure real(dp) function extension(s) result(f)
         real(dp), intent(in) :: s
         real(dp) :: r, sign
         call fold(s, r, sign)
         f = sign*k*(self%length*r - r**2/2.0_dp)
      end function extension
      !> F'(s): k (L - s) on [0, L], extended as the derivative of F (even about 0, odd about L).
      pure real(dp) function slope(s)
         real(dp), intent(in) :: s
         real(dp) :: r, sign, l
         l = self%length
         r = modulo(s, 4.0_dp*l)
         sign = 1.0_dp
         if (r > 2.0_dp*l) r = 4.0_dp*l - r          ! F' even about 0 (and 4L-periodic)
         if (r > l) then                             ! F' odd about L
            r = 2.0_dp*l - r
            sign = -1.0_dp
         end if
         slope = sign*k*(l - r)
      end function slope
      !> s folded into [0, L] and the sign of F there: F(s) = sign F(r).
      pure subroutine fold(s, r, sign)
         real(dp), intent(in) :: s
         real(dp), intent(out) :: r, sign
         real(dp) :: l
         l = self%length
         r = modulo(s, 4.0_dp*l)
         sign = 1.0_dp
         if (r > 2.0_dp*l) then                      ! odd about 0 (and 4L-periodic)
            r = 4.0_dp*l - r
            sign = -1.0_dp
         end if
         if (r > l) r = 2.0_dp*l - r                 ! even about L
      end subroutine fold
   end subroutine exact_fields

   !> Static: max_p |x_p - X_p - u_s(X_p)| under the load factor t (m); else the common |u_cm - u_cm,exact|.
   real(dp) function error_at(self, t, particles, ucm)
      class(column_t), intent(in) :: self
      real(dp), intent(in) :: t, ucm
      type(particles_t), intent(in) :: particles
      if (self%static) then
         error_at = maxval(abs(particles%x - particles%x0 - self%static_displacement(particles%x0, t)))
      else
         error_at = abs(ucm - self%ucm_exact(t))
      end if
   end function error_at

   pure function error_name(self) result(name)
      class(column_t), intent(in) :: self
      character(len=:), allocatable :: name
      if (self%static) then
         name = 'max_p |x_p - X_p - u_static(X_p)|'
      else
         name = '|u_cm - u_cm,exact|'
      end if
   end function error_name

   !> Gravity: f_I += m_I (-g) on every node (the fixed node's force is cleared by the grid solve).
   subroutine add_forces(self, grid, t, cache, particles)
      class(column_t), intent(in) :: self
      type(grid_t), intent(inout) :: grid
      real(dp), intent(in) :: t
      type(shape_cache_t), intent(in) :: cache
      type(particles_t), intent(in) :: particles
      if (grid%mirror) then
         ! the nodal masses hold the mirror image's too (mpm_operations, mirror_fold): the weight of
         ! the column's own particles, sum_p N_Ip m_p (-g), which the scheme reflects with the
         ! internal force
         call p2g_particle_forces(cache, -self%gravity*particles%mass_of, grid)
      else
         grid%force = grid%force - self%gravity*grid%mass  ! = sum_p N_Ip m_p (-g): partition of unity
      end if
   end subroutine add_forces

   !> The fused kernels take the column: its weight is a grid load (grid_loads).
   pure logical function fused_applies(self)
      class(column_t), intent(in) :: self
      fused_applies = .true.
   end function fused_applies

   !> Gravity as a uniform body acceleration -g: f_I += m_I (-g) where the fused kernels assemble the
   !> nodal force, before a mirror's fold (the nodal masses are then the column's own), as add_forces.
   pure function grid_loads(self) result(loads)
      class(column_t), intent(in) :: self
      type(grid_loads_t) :: loads
      loads = grid_loads_t(acceleration=-self%gravity, driven_node=-1, drive_velocity=0.0_dp, drive_dt=1.0_dp)
   end function grid_loads

   !> The static end displacement u_s(L) = -g L^2/(2 c^2) (m), about which the free end oscillates (static:
   !> the law's u_s(L) at full load).
   pure subroutine report(self, names, values)
      class(column_t), intent(in) :: self
      character(len=32), allocatable, intent(out) :: names(:)
      real(dp), allocatable, intent(out) :: values(:)
      names = [character(len=32) :: 'static_end_displacement']
      if (self%static) then
         values = [self%static_displacement(self%length, 1.0_dp)]
      else
         values = [-self%gravity*self%length**2/(2.0_dp*self%wave_speed**2)]
      end if
   end subroutine report

   !> The largest kinetic + strain energy of the exact motion: gravity's work down to u = 2 u_s,
   !> rho g int_0^L 2|u_s| dx = 2 rho g^2 L^3/(3 c^2) (it is all strain energy there).
   pure real(dp) function energy_reference(self, initial_energy)
      class(column_t), intent(in) :: self
      real(dp), intent(in) :: initial_energy
      energy_reference = max(initial_energy, 2.0_dp*self%density*self%gravity**2*self%length**3/ &
                             (3.0_dp*self%wave_speed**2), tiny(1.0_dp))
   end function energy_reference
   function column_amplitude_source(self) result(text)
      class(column_input_t), intent(in) :: self
      character(len=:), allocatable :: text
      text = 'gravity (or length)'
   end function column_amplitude_source

end module mpm_scene_column
