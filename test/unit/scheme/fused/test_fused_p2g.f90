!> Shape functions and particle-to-grid transfer: partition of unity, linear completeness,
!> conservation of mass and momentum, and the first moment of mass.
program test_fused_p2g
   use mpm_kinds, only: dp
   use mpm_errors, only: error_t
   use mpm_shape_linear, only: locate, shape_left, shape_right
   use mpm_grid, only: grid_t, grid_init, assemble_nodes
   use mpm_particles, only: particles_t, particles_init
   use mpm_transfer, only: pass_totals_t, p2g
   use mpm_segments, only: segments_t
   use mpm_testing, only: tester_t, tester
   implicit none
   type(tester_t) :: t
   type(grid_t) :: grid
   type(particles_t) :: particles
   type(pass_totals_t) :: totals
   type(segments_t) :: seg
   type(error_t), allocatable :: error
   real(dp) :: x, xi, r, total_mass, first_moment
   integer :: i, e
   real(dp), parameter :: length = 7.0_dp
   integer, parameter :: elements = 7, per_element = 3

   t = tester('test_fused_p2g')
   ! Partition of unity and linear completeness at pseudo-random points, and the located
   ! element really contains the point.
   if (t%case('locate_and_hat')) then
      do i = 1, 1000
         call random_number(r)
         x = r*length
         call locate(x, elements/length, elements, e, xi)
         call t%check('located element in range', e >= 1 .and. e <= elements)
         call t%check_close('partition of unity', shape_left(xi) + shape_right(xi), 1.0_dp, atol=1.0e-15_dp)
         ! sum N_I x_I = x for nodes x_{e-1} = (e-1) dx, x_e = e dx (dx = 1 here)
         call t%check_close('linear completeness', shape_left(xi)*(e - 1) + shape_right(xi)*e, x, rtol=1.0e-14_dp)
      end do
      call locate(length, elements/length, elements, e, xi)
      call t%check('far end belongs to the last element', e == elements .and. xi == 1.0_dp)
      call locate(-1.0e-9_dp, elements/length, elements, e, xi)
      call t%check('left of the grid is flagged', e == 0)
      call locate(length*(1 + 1.0e-12_dp), elements/length, elements, e, xi)
      call t%check('right of the grid is flagged', e == elements + 1)
   end if

   ! P2G conserves mass and momentum and reproduces the first moment of mass (linear shapes).
   if (t%case('p2g_conservation')) then
      call particles_init(particles, elements, per_element, length/elements, 2.5_dp, error)
      call t%check('particles allocated', .not. allocated(error))
      call grid_init(grid, elements, length, particles%mass, error, fixed=[0])
      do i = 1, particles%count
         call random_number(r)
         particles%x(i) = particles%x(i) + (r - 0.5_dp)*0.3_dp ! move them off the sub-cell centres
         call random_number(r)
         particles%v(i) = 2*r - 1
      end do
      call p2g(particles, grid, seg, .true., totals)
      call assemble_nodes(grid, .true.)
      total_mass = particles%mass*particles%count
      call t%check_close('total particle mass = rho L', total_mass, 2.5_dp*length, rtol=1.0e-14_dp)
      call t%check_close('mass conserved', sum(grid%mass), total_mass, rtol=1.0e-14_dp)
      call t%check_close('momentum conserved (before the fixed node is zeroed)', &
                         sum(grid%element_momentum_left) + sum(grid%element_momentum_right), &
                         particles%mass*sum(particles%v), rtol=1.0e-13_dp, atol=1.0e-13_dp)
      first_moment = sum([(grid%mass(i)*i*grid%dx, i=0, elements)])
      call t%check_close('first moment of mass', first_moment, particles%mass*sum(particles%x), rtol=1.0e-13_dp)
      call t%check('fixed node has no momentum', grid%momentum(0) == 0.0_dp .and. grid%force(0) == 0.0_dp)
      ! internal forces of a free body sum to zero: sum_I f_I = -sum_p sum_I dN_I sigma V = 0 (sum dN = 0)
      particles%stress = 1.0_dp
      call p2g(particles, grid, seg, .true., totals)
      call assemble_nodes(grid, .true.)
      call t%check_close('internal forces sum to zero except the reaction', sum(grid%force(1:)), &
                         -sum(grid%element_stress_volume(1:1))*grid%inv_dx, rtol=1.0e-12_dp)
      call t%check_close('kinetic energy of the pass', totals%kinetic_energy, 0.5_dp*particles%mass*sum(particles%v**2), &
                         rtol=1.0e-13_dp)
   end if
   call t%finish()
end program test_fused_p2g
