// Griffiths & Lane's slope (geometries/slope_gl.geo) at 60 degrees: the
// same 10 m height, firm base at the toe, crest 12 m wide behind the slope
// and footing surface, for the undrained slope of test_fos.sh.
L = 10 / Tan(Pi / 3);
Include "../../../geometries/slope_gl.geo";
