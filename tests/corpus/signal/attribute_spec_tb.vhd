-- Family 15: user-defined attribute declarations and specifications (on a quantity and on a label), read
-- in a simultaneous statement.  vin = 1 - exp(-t/1 ms) (RC charge);  vout = vin'gain*vin = 3*vin
library ieee;
use ieee.electrical_systems.all;

entity attribute_spec_tb is
end entity attribute_spec_tb;

architecture behav of attribute_spec_tb is
  attribute gain : real;
  attribute unit_name : string;
  terminal a, b : electrical;
  quantity vs across isrc through a to electrical_ref;
  quantity vr across ir through a to b;
  quantity vin across ic through b to electrical_ref;
  quantity vout : real;
  attribute gain of vin : quantity is 3.0;
  attribute unit_name of vout : quantity is "V";
  attribute unit_name of amp : label is "amplifier";
begin
  if domain = quiescent_domain use
    vs == 0.0;
  else
    vs == 1.0;
  end use;
  vr == 1.0e3 * ir;
  ic == 1.0e-6 * vin'dot;
  amp : vout == vin'gain * vin;
end architecture behav;
