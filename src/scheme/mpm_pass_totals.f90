!> What a pass over the particles, or a whole step, reports to the run: the sums and extremes its
!> guards and history read (displacement, energies, smallest J, furthest move, first particle outside)
!> and, for bodies on stacked fields, each body's own. Every stepper (generic, fused, implicit) fills
!> one per step; a scene's watch reads it (mpm_scene).
module mpm_pass_totals
   use mpm_kinds, only: dp
   implicit none
   private
   public :: pass_totals_t, max_bodies

   !> The most bodies on stacked fields whose own totals a pass carries: the fused kernels' variant
   !> `bodies` sums them per body for the scenes that watch each body (an impact's two bars); a run
   !> with more bodies gets no per-body totals (pass_totals_t%bodies = 0).
   integer, parameter :: max_bodies = 2

   !> Sums and extremes gathered during a pass over the particles.
   type :: pass_totals_t
      !> sum_p (x_p - X_p) after the pass (fused path: equal masses, count * u_cm), or sum_p m_p (x_p - X_p)
      !> (generic path: total mass * u_cm).
      real(dp) :: displacement = 0.0_dp
      !> sum_p m_p v_p^2 / 2 with the velocities after the pass (when the pass updates them).
      real(dp) :: kinetic_energy = 0.0_dp
      !> sum_p sigma_p^2 V_p / (2E) with the stresses after the pass (when the pass updates them).
      real(dp) :: strain_energy = 0.0_dp
      !> plastic work done so far, sum_p (sigma_y alpha + H alpha^2/2) V0 (elastoplastic law; else 0).
      real(dp) :: plastic_work = 0.0_dp
      !> smallest volume ratio J seen (after the update, when the pass updates it).
      real(dp) :: min_volume_ratio = huge(1.0_dp)
      !> largest |x_new - x_old| / dx of the pass (when the pass moves particles).
      real(dp) :: max_cell_move = 0.0_dp
      !> the particle that moved furthest in the pass.
      integer :: furthest = 0
      !> first particle found outside the grid, 0 if none.
      integer :: outside = 0
      !> Bodies on stacked fields (the fused kernels' variant `bodies`, at most max_bodies; else 0): the
      !> number of bodies, each body's sum_p m_p (x_p - X_p) and sum_p m_p v_p (when the pass moves the
      !> particles) and the smallest stress of all (when it updates the stress), summed in lanes per
      !> segment, then over the segments in order; the impact's watch reads them (mpm_scene_impact).
      integer :: bodies = 0
      real(dp) :: body_displacement(max_bodies) = 0.0_dp, body_momentum(max_bodies) = 0.0_dp
      real(dp) :: min_stress = huge(1.0_dp)
   end type pass_totals_t

end module mpm_pass_totals
