-- Family 20: a case statement and VHDL-2008's conditional and selected assignments in a process (each is the if
-- statement it is equivalent to). sel = floor(t / 1 ms) (a stimulus process); the decoder runs when sel changes:
--   case sel: 0 => lv := 1; 1 | 2 => lv := 2 * sel; others => lv := -1       (a case statement)
--   gain := 10 when sel > 1 else 1                                            (conditional variable assignment)
--   with sel select st := 0.5 when 0 | 1, 1.5 when others                     (selected variable assignment)
--   flag <= 1 when sel = 2 else 0                                             (conditional signal assignment)
--   with sel select third <= 0.25 when 0, st when others                      (selected signal assignment)
--   y == lv:          1, 2, 4, -1, -1       for sel = 0, 1, 2, 3, 4
--   w == gain * lv:   1, 2, 40, -10, -10
--   s == third + flag: 0.25, 0.5, 2.5, 1.5, 1.5
library ieee;
use ieee.math_real.all;

entity sequential_case_tb is
end entity sequential_case_tb;

architecture behav of sequential_case_tb is
  signal sel : integer := 0;
  signal level, out2, third, flag : real := 0.0;
  quantity y, w, s : real;
begin
  count : process is
  begin
    wait for 1 ms;
    sel <= sel + 1;
  end process count;

  decode : process (sel) is
    variable lv, gain, st : real := 0.0;
  begin
    case sel is
      when 0 => lv := 1.0;
      when 1 | 2 => lv := 2.0 * real(sel);
      when others => lv := -1.0;
    end case;
    gain := 10.0 when sel > 1 else 1.0;
    with sel select st := 0.5 when 0 | 1, 1.5 when others;
    level <= lv;
    out2 <= gain * lv;
    flag <= 1.0 when sel = 2 else 0.0;
    with sel select third <= 0.25 when 0, st when others;
  end process decode;

  y == level;
  w == out2;
  s == third + flag;
end architecture behav;
