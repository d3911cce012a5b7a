!> The total-Lagrangian formulation of MPM ([de Vaucorbeil 2020]; references: docs/theory.md): the grid is
!> the reference configuration's, the weights N_I(X_p) and gradients dN_I/dX(X_p) are evaluated once at the
!> particles' reference positions (mpm_operations, locate_particles), the nodal masses never change, and
!>   f_I = -sum_p V0_p P_p dN_I/dX(X_p)   (P = sigma in 1-D: the cross-section does not change),
!>   F_p += dF_p = dt sum_I v_I dN_I/dX(X_p),   x_p += dt sum_I N_I(X_p) v_I.
!> The laws take the log-strain increment dt dv/dx = dF/F (in 1-D F = J), so that J (1 + d eps) = F + dF:
!> F is updated additively, to round-off. Everything else (P2G, the grid solve, the transfers, MUSL's
!> remap, the mirror at a fixed end) is the updated formulation's, with the reference weights.
module mpm_total_lagrangian
   use mpm_kinds, only: dp
   implicit none
   private
   public :: log_strain_increment, reference_stress_volume

contains

   !> dF (the gathered dt sum_I v_I dN_I/dX) into the log-strain increment dF/F the laws take, F = J.
   pure subroutine log_strain_increment(volume_ratio, dstrain)
      real(dp), intent(in), contiguous :: volume_ratio(:)
      real(dp), intent(inout), contiguous :: dstrain(:)
      dstrain = dstrain/volume_ratio
   end subroutine log_strain_increment

   !> P_p V0_p, the factor of -dN_I/dX(X_p) in the internal force.
   pure subroutine reference_stress_volume(stress, volume0, stress_volume)
      real(dp), intent(in), contiguous :: stress(:), volume0(:)
      real(dp), intent(out), contiguous :: stress_volume(:)
      stress_volume = stress*volume0
   end subroutine reference_stress_volume
end module mpm_total_lagrangian
