!> A velocity field per body and frictionless contact between two bodies (multi-velocity-field MPM:
!> [Bardenhagen 2000], [Bardenhagen 2001]; where the correction sits in USF and MUSL as in [Huang 2011];
!> [York 2000] used the same release test on one field; references: docs/theory.md).
!>
!> Each body has its own nodal mass, momentum, force, velocity and acceleration. They are stacked in
!> one grid_t (`fields`): body b's node i is node (b - 1) nodes + i of `fields`. After the shape
!> functions are evaluated on the run's grid, body b's particles (one contiguous range) have their
!> first support node shifted by (b - 1) nodes (and, for APIC, their start-of-step position by as many
!> cells, so x_I - x_p is unchanged): then every generic operation of mpm_operations (P2G, the grid
!> solve, G2P, the stress update; any shape, any transfer) works per body on `fields` unchanged, and
!> a scene without bodies pays nothing for them.
!>
!> Contact at node i: the bodies touch, both have mass at the node and they approach there,
!> (v_1 - v_2) n_1 > 0 with n_1 the outward normal of body 1 (in 1-D +1 or -1: the direction from body
!> 1's centre of mass to body 2's, fixed at the start since frictionless bodies in 1-D cannot pass each
!> other). "Touch": the facing surfaces, each the end of its end particle's domain x_p +- J_p l0_p/2,
!> are at most `touch_tolerance` dx apart at the start of the step. Without this test the bodies would
!> collide as soon as their particles share a node (up to one cell early with linear shapes, more with
!> wider ones): the early-contact error that [Bardenhagen 2001] correct with a distance test too
!> (in several dimensions from nodal volumes; in 1-D the surfaces are known exactly). Then both take the
!> centre-of-mass velocity v_cm = (p_1 + p_2)/(m_1 + m_2) (frictionless: in 1-D the whole velocity is
!> normal), p_b = m_b v_cm, and the acceleration gains (v_cm - v_b)/dt, so FLIP's update sees the
!> contact force. sum_b p_b is unchanged: contact conserves momentum exactly. Otherwise each body keeps
!> its own velocity, so the bodies separate freely.
module mpm_contact
   use mpm_kinds, only: dp
   use mpm_errors, only: error_t, set_error
   use mpm_strings, only: str
   use mpm_grid, only: grid_t, sync_grid
   use mpm_state, only: state_t
   use mpm_particles, only: particles_t
   use mpm_shape, only: shape_cache_t
   use mpm_pass_totals, only: pass_totals_t
   use mpm_operations, only: locate_particles
   implicit none
   private
   public :: bodies_t, bodies_init, locate_bodies, contact_velocities, contact_momentum, combine_bodies, touch_test, &
             contact_correct
   public :: sync_bodies

   !> Largest surface gap, in cells, at which the bodies count as touching (the surface estimate from
   !> the end particles' domains is not exact while they deform).
   real(dp), parameter :: touch_tolerance = 1.0e-3_dp

   !> The per-body fields of a run and where each body's particles are.
   type :: bodies_t
      integer :: count = 0
      integer :: nodes = 0                        !< nodes of the run's grid (elements + 1)
      integer, allocatable :: first(:), last(:)   !< body b's particles: first(b) .. last(b)
      real(dp) :: normal = 1.0_dp                 !< outward normal of body 1 towards body 2
      integer :: contact_nodes = 0                !< nodes corrected in the last correction
      integer :: facing(2) = 0                    !< the end particle of each body facing the other
      logical :: touching = .false.               !< the surfaces touch at the start of this step
      real(dp) :: surface_gap = 0.0_dp            !< their distance then (m; < 0: overlap)
      type(grid_t) :: fields                      !< body b's node i is (b - 1)*nodes + i
      !> The nodes of the fields each body may hold values at (columns: first, last; fused_step keeps it)
      integer, allocatable :: active(:, :)
   end type bodies_t

contains

   !> The per-body fields of `grid` for the particles' bodies (particles%body: 1 .. count, each body a
   !> contiguous range). Two bodies; no mirror ghosts (no fixed end with wide shapes).
   !> With `element_shares` the fields also get the fused kernels' per-element shares.
   subroutine bodies_init(bodies, grid, particles, error, element_shares)
      type(bodies_t), intent(out) :: bodies
      type(grid_t), intent(in) :: grid
      type(particles_t), intent(in) :: particles
      type(error_t), allocatable, intent(out) :: error
      logical, intent(in), optional :: element_shares
      integer :: b, p, stat, total, shares
      real(dp) :: centre(2)
      if (.not. allocated(particles%body)) then
         call set_error(error, 'contact: the scene gave no body index to its particles')
         return
      end if
      bodies%count = maxval(particles%body)
      if (bodies%count /= 2 .or. minval(particles%body) /= 1) then
         call set_error(error, 'contact: frictionless contact needs two bodies, numbered 1 and 2; the scene has '// &
                        str(bodies%count))
         return
      end if
      if (grid%mirror) then
         call set_error(error, 'contact: per-body fields with mirror ghosts at a fixed end are not implemented')
         return
      end if
      allocate (bodies%first(bodies%count), bodies%last(bodies%count))
      bodies%first = particles%count + 1
      bodies%last = 0
      do p = 1, particles%count
         b = particles%body(p)
         bodies%first(b) = min(bodies%first(b), p)
         bodies%last(b) = max(bodies%last(b), p)
      end do
      do b = 1, bodies%count
         if (any(particles%body(bodies%first(b):bodies%last(b)) /= b)) then
            call set_error(error, 'contact: the particles of body '//str(b)//' are not one contiguous range')
            return
         end if
         centre(b) = sum(particles%mass_of(bodies%first(b):bodies%last(b))*particles%x(bodies%first(b):bodies%last(b)))
      end do
      bodies%normal = sign(1.0_dp, centre(2)/sum(particles%mass_of(bodies%first(2):bodies%last(2))) - &
                           centre(1)/sum(particles%mass_of(bodies%first(1):bodies%last(1))))
      ! the facing ends: body 1's furthest particle along the normal, body 2's furthest against it
      if (bodies%normal > 0.0_dp) then
         bodies%facing(1) = bodies%first(1) - 1 + maxloc(particles%x(bodies%first(1):bodies%last(1)), 1)
         bodies%facing(2) = bodies%first(2) - 1 + minloc(particles%x(bodies%first(2):bodies%last(2)), 1)
      else
         bodies%facing(1) = bodies%first(1) - 1 + minloc(particles%x(bodies%first(1):bodies%last(1)), 1)
         bodies%facing(2) = bodies%first(2) - 1 + maxloc(particles%x(bodies%first(2):bodies%last(2)), 1)
      end if
      bodies%nodes = grid%elements + 1
      total = bodies%count*bodies%nodes
      ! the run's grid (origin, dx, length: the domain a particle may not leave), its arrays stacked
      bodies%fields%elements = total - 1
      bodies%fields%dx = grid%dx
      bodies%fields%inv_dx = grid%inv_dx
      bodies%fields%length = grid%length
      bodies%fields%origin = grid%origin
      bodies%fields%empty_mass = grid%empty_mass
      bodies%fields%ghost = grid%ghost
      bodies%fields%mirror = .false.
      bodies%fields%fixed = [(grid%fixed + (b - 1)*bodies%nodes, b=1, bodies%count)]
      allocate (bodies%active(2, bodies%count))
      do b = 1, bodies%count ! (until a step has told: each body's whole field)
         bodies%active(:, b) = [(b - 1)*bodies%nodes, b*bodies%nodes - 1]
      end do
      shares = 0
      if (present(element_shares)) then
         if (element_shares) shares = total - 1
      end if
      allocate (bodies%fields%mass(0:total - 1), bodies%fields%momentum(0:total - 1), bodies%fields%force(0:total - 1), &
                bodies%fields%velocity(0:total - 1), bodies%fields%acceleration(0:total - 1), &
                bodies%fields%element_mass_left(shares), bodies%fields%element_mass_right(shares), &
                bodies%fields%element_momentum_left(shares), bodies%fields%element_momentum_right(shares), &
                bodies%fields%element_stress_volume(shares), bodies%fields%element_strain(shares), stat=stat)
      if (stat /= 0) then
         call set_error(error, 'cannot allocate the per-body fields of '//str(total)//' nodes (out of memory)')
         return
      end if
      bodies%fields%mass = 0.0_dp
      bodies%fields%momentum = 0.0_dp
      bodies%fields%force = 0.0_dp
      bodies%fields%velocity = 0.0_dp
      bodies%fields%acceleration = 0.0_dp
      bodies%fields%element_mass_left = 0.0_dp
      bodies%fields%element_mass_right = 0.0_dp
      bodies%fields%element_momentum_left = 0.0_dp
      bodies%fields%element_momentum_right = 0.0_dp
      bodies%fields%element_stress_volume = 0.0_dp
      bodies%fields%element_strain = 0.0_dp
   end subroutine bodies_init

   !> Shape functions on the run's grid, then each body's support moved onto its own fields; whether
   !> the bodies touch (their facing surfaces, x_p +- J_p V0_p/2 of the end particles, in 1-D).
   subroutine locate_bodies(cache, grid, particles, bodies, totals)
      type(shape_cache_t), intent(inout) :: cache
      type(grid_t), intent(in) :: grid
      type(particles_t), intent(in) :: particles
      type(bodies_t), intent(inout) :: bodies
      type(pass_totals_t), intent(inout) :: totals
      integer :: b, shift
      call locate_particles(cache, grid, particles, totals)
      call touch_test(bodies, particles, grid%dx)
      do b = 2, bodies%count
         shift = (b - 1)*bodies%nodes
         associate (r1 => bodies%first(b), r2 => bodies%last(b))
            cache%first(r1:r2) = cache%first(r1:r2) + shift
            if (allocated(cache%position)) cache%position(r1:r2) = cache%position(r1:r2) + shift*grid%dx
         end associate
      end do
   end subroutine locate_bodies

   !> Whether the bodies touch at the start of the step: their facing surfaces, x_p +- J_p V0_p/2 of the
   !> end particles (in 1-D), at most touch_tolerance cells of size dx apart.
   subroutine touch_test(bodies, particles, dx)
      type(bodies_t), intent(inout) :: bodies
      type(particles_t), intent(in) :: particles
      real(dp), intent(in) :: dx
      associate (p1 => bodies%facing(1), p2 => bodies%facing(2))
         bodies%surface_gap = bodies%normal*((particles%x(p2) - bodies%normal*0.5_dp*particles%volume_ratio(p2)* &
                                              particles%volume0_of(p2)) - &
                                             (particles%x(p1) + bodies%normal*0.5_dp*particles%volume_ratio(p1)* &
                                              particles%volume0_of(p1)))
      end associate
      bodies%touching = bodies%surface_gap <= touch_tolerance*dx
   end subroutine touch_test

   !> After the nodal velocities (USF, MUSL's remap): approaching bodies share v_cm (momentum too).
   subroutine contact_velocities(bodies)
      type(bodies_t), intent(inout) :: bodies
      call correct(bodies, 0.0_dp)
   end subroutine contact_velocities

   !> After the grid solve: approaching bodies share v_cm; the acceleration takes the contact force.
   subroutine contact_momentum(bodies, dt)
      type(bodies_t), intent(inout) :: bodies
      real(dp), intent(in) :: dt
      call correct(bodies, dt)
   end subroutine contact_momentum

   !> The correction of both: with dt > 0 also a_b += (v_cm - v_b)/dt.
   subroutine correct(bodies, dt)
      type(bodies_t), intent(inout) :: bodies
      real(dp), intent(in) :: dt
      call contact_correct(bodies%fields, bodies%nodes, bodies%normal, bodies%touching, dt, bodies%contact_nodes)
   end subroutine correct

   !> The correction on the stacked fields `f` of two bodies of `n` nodes each (normal, touching: see
   !> bodies_t; `corrected`: the nodes corrected), for a caller that holds the fields apart from bodies_t's
   !> other components (the fused kernels' step).
   subroutine contact_correct(f, n, normal, touching, dt, corrected)
      type(grid_t), intent(inout) :: f
      integer, intent(in) :: n
      real(dp), intent(in) :: normal, dt
      logical, intent(in) :: touching
      integer, intent(out) :: corrected
      integer :: i, j
      real(dp) :: vcm
      corrected = 0
      if (.not. touching) return
      do i = 0, n - 1
         j = i + n
         if (f%mass(i) <= f%empty_mass .or. f%mass(j) <= f%empty_mass) cycle
         if ((f%velocity(i) - f%velocity(j))*normal <= 0.0_dp) cycle ! separating or at rest
         corrected = corrected + 1
         vcm = (f%momentum(i) + f%momentum(j))/(f%mass(i) + f%mass(j))
         if (dt > 0.0_dp) then
            f%acceleration(i) = f%acceleration(i) + (vcm - f%velocity(i))/dt
            f%acceleration(j) = f%acceleration(j) + (vcm - f%velocity(j))/dt
         end if
         f%velocity(i) = vcm
         f%velocity(j) = vcm
         f%momentum(i) = f%mass(i)*vcm
         f%momentum(j) = f%mass(j)*vcm
      end do
   end subroutine contact_correct

   !> The run's grid as the bodies' sum (mass, momentum, force; velocity p/m), for snapshots and the
   !> guards' lightest node. One loop over the nodes (the sums body by body, in body order).
   subroutine combine_bodies(bodies, grid)
      type(bodies_t), intent(in) :: bodies
      type(grid_t), intent(inout) :: grid
      grid%min_node_mass = bodies%fields%min_node_mass
      call sum_fields(bodies%count, bodies%nodes, bodies%fields%mass, bodies%fields%momentum, bodies%fields%force, &
                      grid%empty_mass, grid%mass, grid%momentum, grid%force, grid%velocity)
   end subroutine combine_bodies

   !> The bodies' stacked fields (count bodies of n nodes each) summed node by node, body 1 first, and the
   !> velocity p/m where the mass exceeds empty_mass (zero elsewhere).
   subroutine sum_fields(count, n, mass, momentum, force, empty_mass, total_mass, total_momentum, total_force, velocity)
      integer, intent(in) :: count, n
      real(dp), intent(in), contiguous :: mass(0:), momentum(0:), force(0:)
      real(dp), intent(in) :: empty_mass
      real(dp), intent(out), contiguous :: total_mass(0:), total_momentum(0:), total_force(0:), velocity(0:)
      integer :: i, b
      real(dp) :: m, p, f
      do i = 0, n - 1
         m = mass(i)
         p = momentum(i)
         f = force(i)
         do b = 2, count
            m = m + mass((b - 1)*n + i)
            p = p + momentum((b - 1)*n + i)
            f = f + force((b - 1)*n + i)
         end do
         total_mass(i) = m
         total_momentum(i) = p
         total_force(i) = f
         if (m > empty_mass) then
            velocity(i) = p/m
         else
            velocity(i) = 0.0_dp
         end if
      end do
   end subroutine sum_fields

   !> What the bodies' fields carry from one step to the next, to or from `state` (under bodies.*, as
   !> state%saving says), for a checkpoint.
   subroutine sync_bodies(state, bodies)
      type(state_t), intent(inout) :: state
      type(bodies_t), intent(inout) :: bodies
      call state%sync('bodies.first', bodies%first)
      call state%sync('bodies.last', bodies%last)
      call state%sync('bodies.normal', bodies%normal)
      call state%sync('bodies.contact_nodes', bodies%contact_nodes)
      call state%sync('bodies.facing1', bodies%facing(1))
      call state%sync('bodies.facing2', bodies%facing(2))
      call state%sync('bodies.touching', bodies%touching)
      call state%sync('bodies.surface_gap', bodies%surface_gap)
      call state%sync('bodies.active', bodies%active)
      call sync_grid(state, 'bodies.fields', bodies%fields)
   end subroutine sync_bodies
end module mpm_contact
