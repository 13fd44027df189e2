// Decodes LCM messages with the Java classes of build/drivers/prepreg_lcmtypes.jar, the way
// lcm-spy does (the class's byte[] constructor, which checks the fingerprint), and prints each
// message's public fields as name=value lines, arrays as [a, b, ...].
// Usage: java -cp lcm.jar:prepreg_lcmtypes.jar LcmTypesDecode.java CLASS FILE [CLASS FILE ...]
import java.lang.reflect.Array;
import java.lang.reflect.Field;
import java.lang.reflect.Modifier;
import java.nio.file.Files;
import java.nio.file.Paths;

public class LcmTypesDecode {
  static String text(Object v) {
    if (v == null || !v.getClass().isArray()) return String.valueOf(v);
    StringBuilder s = new StringBuilder("[");
    for (int i = 0; i < Array.getLength(v); ++i) s.append(i > 0 ? ", " : "").append(text(Array.get(v, i)));
    return s.append("]").toString();
  }

  public static void main(String[] args) throws Exception {
    for (int a = 0; a + 1 < args.length; a += 2) {
      Class<?> c = Class.forName(args[a]);
      byte[] bytes = Files.readAllBytes(Paths.get(args[a + 1]));
      Object msg = c.getConstructor(byte[].class).newInstance(bytes);
      System.out.println("type " + c.getName());
      for (Field f : c.getFields()) {
        if (Modifier.isStatic(f.getModifiers())) continue;
        System.out.println(f.getName() + "=" + text(f.get(msg)));
      }
    }
  }
}
