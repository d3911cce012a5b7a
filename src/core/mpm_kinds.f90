!> Working precision and the few numerical constants the whole code shares.
module mpm_kinds
   use, intrinsic :: iso_fortran_env, only: real64, int64
   implicit none
   private
   public :: dp, i8, pi

   !> Double precision for every real in the code.
   integer, parameter :: dp = real64
   !> 64-bit integers for counts that may exceed 2**31 (particle-steps, sizes in bytes).
   integer, parameter :: i8 = int64
   !> Archimedes' constant.
   real(dp), parameter :: pi = 3.14159265358979323846264338327950288_dp
end module mpm_kinds
