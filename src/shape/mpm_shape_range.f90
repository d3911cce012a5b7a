!> The range test every shape makes for every particle, written so that the shape loops vectorise:
!> lo <= s <= hi (NaN: outside) by integer arithmetic on the bit patterns of s - lo and hi - s, because
!> gfortran keeps a loop with a floating-point comparison scalar under its default -ftrapping-math
!> (the shape loops then ran about 3x slower). The hot loops write the two lines of inside_range out
!> (gfortran does not inline a function of another module), with the same names:
!>    below = transfer(s - lo, 0_i8); above = transfer(hi - s, 0_i8)
!>    flag = int(1_i8 - ishft(ior(ior(below, above), infinity_bits - below), -63))
!> test_shape_functions checks inside_range and, through the shapes, the written-out copies.
module mpm_shape_range
   use mpm_kinds, only: dp, i8
   implicit none
   private
   public :: inside_range, infinity_bits

   !> Bit pattern of +Infinity: non-negative doubles order as their bit patterns, NaNs above it.
   integer(i8), parameter :: infinity_bits = int(z'7FF0000000000000', i8)

contains

   !> 1 when lo <= s <= hi, 0 otherwise (NaN included): both s - lo and hi - s have a clear sign bit
   !> and s - lo is not a NaN (non-negative doubles order as their bit patterns, NaNs above +Inf).
   elemental integer function inside_range(s, lo, hi) result(flag)
      real(dp), intent(in) :: s, lo, hi
      integer(i8) :: below, above
      below = transfer(s - lo, 0_i8)
      above = transfer(hi - s, 0_i8)
      flag = int(1_i8 - ishft(ior(ior(below, above), infinity_bits - below), -63))
   end function inside_range
end module mpm_shape_range
